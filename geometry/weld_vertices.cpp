#include "geometry/weld_vertices.h"
