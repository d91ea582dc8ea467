#include "geometry/paper_bodies.h"
