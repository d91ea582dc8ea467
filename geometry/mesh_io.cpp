#include "geometry/mesh_io.h"
