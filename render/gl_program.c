/* Compiling and linking a GLSL program, shared by the stereo pass (renderer.c) and the distortion
 * pass (distortion.c), so both report a shader's log the same way. */
#include "render/render_internal.h"

#include <GL/gl.h>
#include <GL/glext.h>

static GLuint compile(GLenum type, const char *src, const char *who, struct hl_error *err)
{
    GLuint sh = glCreateShader(type);
    glShaderSource(sh, 1, &src, NULL);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[400] = "";
        glGetShaderInfoLog(sh, sizeof log, NULL, log);
        glDeleteShader(sh);
        hl_fail(err, "%s: %s shader does not compile: %s", who, type == GL_VERTEX_SHADER ? "vertex" : "fragment",
                log);
        return 0;
    }
    return sh;
}

unsigned rnd_gl_program_build(const char *vertex_src, const char *fragment_src, const char *who, struct hl_error *err)
{
    GLuint vs = compile(GL_VERTEX_SHADER, vertex_src, who, err);
    GLuint fs = vs ? compile(GL_FRAGMENT_SHADER, fragment_src, who, err) : 0;
    if (!fs) {
        glDeleteShader(vs);
        return 0;
    }
    GLuint program = glCreateProgram();
    glAttachShader(program, vs);
    glAttachShader(program, fs);
    glLinkProgram(program);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[400] = "";
        glGetProgramInfoLog(program, sizeof log, NULL, log);
        glDeleteProgram(program);
        hl_fail(err, "%s: shader program does not link: %s", who, log);
        return 0;
    }
    return program;
}
