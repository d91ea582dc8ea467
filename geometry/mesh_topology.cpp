#include "geometry/mesh_topology.h"
