#pragma once
/// OpenGL 3.3 core entry points. Linux's libGL exports every core function, so the prototypes of glext.h serve and
/// no loader is needed.

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
