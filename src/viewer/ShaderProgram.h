#pragma once
/// A linked GLSL program (vertex and fragment shader); needs a current GL context.

#include "GlHeaders.h"

namespace masse::viewer
{
class ShaderProgram
{
public:
    /// Compiles and links; throws std::runtime_error with the driver's log if either shader or the link fails.
    ShaderProgram(const char* vertexSource, const char* fragmentSource);
    ~ShaderProgram();
    ShaderProgram(const ShaderProgram&) = delete;
    ShaderProgram& operator=(const ShaderProgram&) = delete;

    void use() const { glUseProgram(m_program); }
    GLint uniform(const char* name) const { return glGetUniformLocation(m_program, name); }

private:
    GLuint m_program = 0;
};
} // namespace masse::viewer
