#pragma once
// The OpenGL 3.3 core declarations the drawing code uses; the symbols come from the library that
// made the context (libOSMesa here, see gl_context.h), so no loader is needed.

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
