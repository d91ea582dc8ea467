#include "geometry/convex_hull.h"
