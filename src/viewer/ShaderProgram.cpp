#include "ShaderProgram.h"

#include <stdexcept>
#include <string>

namespace masse::viewer
{
namespace
{
GLuint compile(GLenum kind, const char* source)
{
    const GLuint shader = glCreateShader(kind);
    glShaderSource(shader, 1, &source, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok)
    {
        char log[2048] = {};
        glGetShaderInfoLog(shader, sizeof log, nullptr, log);
        glDeleteShader(shader);
        throw std::runtime_error(std::string(kind == GL_VERTEX_SHADER ? "vertex" : "fragment") +
                                 " shader does not compile: " + log);
    }
    return shader;
}
} // namespace

ShaderProgram::ShaderProgram(const char* vertexSource, const char* fragmentSource)
{
    const GLuint vertex = compile(GL_VERTEX_SHADER, vertexSource);
    GLuint fragment = 0;
    try
    {
        fragment = compile(GL_FRAGMENT_SHADER, fragmentSource);
    }
    catch (...)
    {
        glDeleteShader(vertex);
        throw;
    }
    m_program = glCreateProgram();
    glAttachShader(m_program, vertex);
    glAttachShader(m_program, fragment);
    glLinkProgram(m_program);
    glDeleteShader(vertex);
    glDeleteShader(fragment);
    GLint ok = 0;
    glGetProgramiv(m_program, GL_LINK_STATUS, &ok);
    if (!ok)
    {
        char log[2048] = {};
        glGetProgramInfoLog(m_program, sizeof log, nullptr, log);
        glDeleteProgram(m_program);
        throw std::runtime_error(std::string("shader program does not link: ") + log);
    }
}

ShaderProgram::~ShaderProgram()
{
    glDeleteProgram(m_program);
}
} // namespace masse::viewer
