#include "geometry/contact_patch.h"
