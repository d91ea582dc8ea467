#include "geometry/convex_shape.h"
