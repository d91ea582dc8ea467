#include "engine/state.h"
