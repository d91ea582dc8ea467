#include "engine/time_step.h"
