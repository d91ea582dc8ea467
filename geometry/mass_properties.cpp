#include "geometry/mass_properties.h"
