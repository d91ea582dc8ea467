#include "engine/loads.h"
