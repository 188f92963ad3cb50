/*
 * A persp scene rendered by Mesa through OSMesa, as an OpenGL programmer
 * would draw it for speed: one vertex buffer, index buffer and vertex array
 * object per scene object, drawn with glDrawElements; one texture object per
 * scene texture holding every mip level persp built (so both sample the same
 * texels), with the filter and wrap in sampler objects; uniforms set per
 * object; a constant light-count loop in the fragment shader.
 *
 * Conventions where GL and persp differ are decided in docs/PERFORMANCE.md
 * ("The OpenGL peer"); the comments below cite the GL 2.1 sections that
 * define the fixed-function behaviour matched.
 *
 * Mesa 22.3's OSMesa offers OSMesaCreateContextAttribs (compatibility
 * profile, GL 4.5 on llvmpipe, 3.3 on softpipe), which has both the
 * fixed-function pipeline and GLSL 1.30, sampler objects (GL 3.3) and
 * GL_EXT_texture_filter_anisotropic on both drivers.
 */
#define GL_GLEXT_PROTOTYPES 1
#include "peer.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef GL_TEXTURE_MAX_ANISOTROPY_EXT
#define GL_TEXTURE_MAX_ANISOTROPY_EXT 0x84FE
#endif
#ifndef GL_MAX_TEXTURE_MAX_ANISOTROPY_EXT
#define GL_MAX_TEXTURE_MAX_ANISOTROPY_EXT 0x84FF
#endif

#if defined(__SANITIZE_ADDRESS__)
/* OSMesa keeps every framebuffer it creates on a process-wide list that it
 * never frees (Mesa 22.3, src/gallium/frontends/osmesa); LeakSanitizer would
 * report that as ours. This is LeakSanitizer's documented hook for default
 * suppressions, built only into sanitizer builds. */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void) { return "leak:libOSMesa.so\n"; }
const char *__lsan_default_options(void);
const char *__lsan_default_options(void) { return "print_suppressions=0"; }
#endif

/* Interleaved vertex: position, normal, texture coordinate, colour. */
#define VERTEX_FLOATS 12
#define MAX_PROGRAMS 8

typedef enum peer_path { PATH_UNLIT, PATH_FIXED, PATH_GLSL } peer_path;

/* Uniform locations of one program, looked up once. */
typedef struct peer_program {
    GLuint name;
    GLint mvp, mv, nm, ambient, diffuse, specular, shininess;
} peer_program;

typedef struct peer_object {
    GLuint vao, vbo, ibo;
    GLsizei count;
    int indexed;
    float mv[16], mvp[16], nm[9];
    persp_scene_material mat;
    GLuint texture, sampler; /* 0: untextured */
    int program;             /* index into programs (PATH_GLSL) */
    int mirrored;            /* the model matrix mirrors: front faces clockwise */
} peer_object;

struct bench_peer {
    OSMesaContext gl;
    int width, height;
    uint8_t *color;
    peer_path path;
    int flat, noperspective;
    const char *pipeline;
    float aniso;
    float clear[4];
    float ambient[3];
    int light_count;
    float light_pos[8][4], light_color[8][3], light_atten[8][3]; /* eye space */
    GLuint *textures;
    size_t texture_count;
    peer_object *objects;
    size_t object_count;
    peer_program programs[MAX_PROGRAMS];
    char renderer[128], version[128];
};

/* persp filter -> GL min / mag filter (GL 4.5 §8.14, Table 8.19). */
static int gl_filters(persp_filter f, GLint *min_filter, GLint *mag_filter)
{
    switch (f) {
    case PERSP_FILTER_NEAREST: *min_filter = GL_NEAREST, *mag_filter = GL_NEAREST; return 1;
    case PERSP_FILTER_BILINEAR: *min_filter = GL_LINEAR, *mag_filter = GL_LINEAR; return 1;
    case PERSP_FILTER_NEAREST_MIP_NEAREST:
        *min_filter = GL_NEAREST_MIPMAP_NEAREST, *mag_filter = GL_NEAREST;
        return 1;
    case PERSP_FILTER_BILINEAR_MIP_NEAREST:
        *min_filter = GL_LINEAR_MIPMAP_NEAREST, *mag_filter = GL_LINEAR;
        return 1;
    case PERSP_FILTER_NEAREST_MIP_LINEAR:
        *min_filter = GL_NEAREST_MIPMAP_LINEAR, *mag_filter = GL_NEAREST;
        return 1;
    case PERSP_FILTER_TRILINEAR:
    case PERSP_FILTER_ANISO:
        *min_filter = GL_LINEAR_MIPMAP_LINEAR, *mag_filter = GL_LINEAR;
        return 1;
    default: return 0;
    }
}

int bench_peer_supports(persp_filter filter)
{
    GLint min_filter, mag_filter;
    return filter == PERSP_FILTER_DEFAULT || gl_filters(filter, &min_filter, &mag_filter);
}

static GLint gl_wrap(persp_wrap w)
{
    switch (w) {
    case PERSP_WRAP_CLAMP_TO_EDGE: return GL_CLAMP_TO_EDGE;
    case PERSP_WRAP_MIRRORED_REPEAT: return GL_MIRRORED_REPEAT;
    case PERSP_WRAP_CLAMP_TO_BORDER: return GL_CLAMP_TO_BORDER;
    default: return GL_REPEAT;
    }
}

/* Every level persp built, as the texture's mip chain (GL 2.1 §3.8.8: a
 * complete texture needs levels down to 1×1, which persp's chain has). */
static int upload_texture(const persp_texture *t, GLuint *name, char *err, size_t err_size)
{
    glGenTextures(1, name);
    glBindTexture(GL_TEXTURE_2D, *name);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    int levels = persp_texture_levels(t);
    for (int l = 0; l < levels; l++) {
        persp_image_view v;
        if (persp_texture_level(t, l, &v) != PERSP_OK || v.stride % 4) {
            snprintf(err, err_size, "peer: unreadable texture level %d", l);
            return 0;
        }
        glPixelStorei(GL_UNPACK_ROW_LENGTH, (GLint)(v.stride / 4));
        glTexImage2D(GL_TEXTURE_2D, l, GL_RGBA8, v.width, v.height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                     v.pixels);
    }
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, levels - 1);
    return 1;
}

static int make_sampler(bench_peer *p, const bench_peer_desc *d, const persp_sampler_desc *s,
                        GLuint *name, char *err, size_t err_size)
{
    persp_filter f = d->filter != PERSP_FILTER_DEFAULT ? d->filter : s->filter;
    if (f == PERSP_FILTER_DEFAULT) f = PERSP_FILTER_BILINEAR;
    GLint min_filter, mag_filter;
    if (!gl_filters(f, &min_filter, &mag_filter)) {
        snprintf(err, err_size, "peer: filter '%s' has no OpenGL counterpart", persp_filter_name(f));
        return 0;
    }
    glGenSamplers(1, name);
    glSamplerParameteri(*name, GL_TEXTURE_MIN_FILTER, min_filter);
    glSamplerParameteri(*name, GL_TEXTURE_MAG_FILTER, mag_filter);
    glSamplerParameteri(*name, GL_TEXTURE_WRAP_S, gl_wrap(s->wrap_s));
    glSamplerParameteri(*name, GL_TEXTURE_WRAP_T, gl_wrap(s->wrap_t));
    float border[4];
    for (int c = 0; c < 4; c++) border[c] = (float)s->border[c] / 255.0f;
    glSamplerParameterfv(*name, GL_TEXTURE_BORDER_COLOR, border);
    if (s->lod_bias != 0.0f) glSamplerParameterf(*name, GL_TEXTURE_LOD_BIAS, s->lod_bias);
    if (s->lod_clamp == PERSP_TOGGLE_ON) {
        glSamplerParameterf(*name, GL_TEXTURE_MIN_LOD, s->min_lod);
        glSamplerParameterf(*name, GL_TEXTURE_MAX_LOD, s->max_lod);
    }
    if (f == PERSP_FILTER_ANISO) {
        const char *ext = (const char *)glGetString(GL_EXTENSIONS);
        if (!ext || !strstr(ext, "GL_EXT_texture_filter_anisotropic")) {
            snprintf(err, err_size, "peer: %s does not offer GL_EXT_texture_filter_anisotropic",
                     p->renderer);
            return 0;
        }
        GLfloat limit = 1.0f;
        glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY_EXT, &limit);
        int taps = d->max_aniso > 0 ? d->max_aniso : s->max_aniso > 0 ? s->max_aniso : 16;
        float want = (float)taps;
        p->aniso = want < limit ? want : limit;
        glSamplerParameterf(*name, GL_TEXTURE_MAX_ANISOTROPY_EXT, p->aniso);
    }
    return 1;
}

/* ------------------------------------------------------------------ GLSL */

static const char *vertex_src =
    "#version 130\n"
    "in vec3 a_pos;\n"
    "in vec3 a_normal;\n"
    "in vec2 a_uv;\n"
    "uniform mat4 u_mvp, u_mv;\n"
    "uniform mat3 u_nm;\n"
    "out vec3 v_eye;\n"
    "NORMAL_QUALIFIER out vec3 v_normal;\n"
    "out vec2 v_uv;\n"
    "void main() {\n"
    "    vec4 p = vec4(a_pos, 1.0);\n"
    "    v_eye = (u_mv * p).xyz;\n"
    "    v_normal = u_nm * a_normal;\n"
    "    v_uv = a_uv;\n"
    "    gl_Position = u_mvp * p;\n"
    "}\n";

/* Blinn–Phong with a local viewer, lights in eye space; w = 0 marks a
 * directional light (its attenuation uniform is then (1, 0, 0)). The same
 * terms as persp's src/shade/shade.c: the texel multiplies ambient +
 * diffuse, the specular term is added after it (times the texel with a
 * specular texture). */
static const char *fragment_src =
    "#version 130\n"
    "NORMAL_QUALIFIER in vec3 v_normal;\n"
    "in vec3 v_eye;\n"
    "in vec2 v_uv;\n"
    "uniform vec3 u_ambient, u_diffuse, u_specular;\n"
    "uniform float u_shininess;\n"
    "#if NUM_LIGHTS > 0\n"
    "uniform vec4 u_light_pos[NUM_LIGHTS];\n"
    "uniform vec3 u_light_color[NUM_LIGHTS];\n"
    "uniform vec3 u_light_atten[NUM_LIGHTS];\n"
    "#endif\n"
    "#if TEXTURED\n"
    "uniform sampler2D u_tex;\n"
    "#endif\n"
    "void main() {\n"
    "#if TEXTURED && !MODULATE\n"
    "    gl_FragColor = texture(u_tex, v_uv);\n"
    "#else\n"
    "    vec3 n = normalize(v_normal);\n"
    "    if (!gl_FrontFacing) n = -n;\n"
    "    vec3 v = normalize(-v_eye);\n"
    "    vec3 d = u_ambient, s = vec3(0.0);\n"
    "#if NUM_LIGHTS > 0\n"
    "    for (int i = 0; i < NUM_LIGHTS; i++) {\n"
    "        vec3 l = u_light_pos[i].xyz - v_eye * u_light_pos[i].w;\n"
    "        float dist = length(l);\n"
    "        l /= dist;\n"
    "        vec3 k = u_light_atten[i];\n"
    "        float att = 1.0 / (k.x + (k.y + k.z * dist) * dist);\n"
    "        float ndl = dot(n, l);\n"
    "        if (ndl > 0.0) {\n"
    "            float ndh = max(dot(n, normalize(l + v)), 0.0);\n"
    "            d += (att * ndl) * u_light_color[i] * u_diffuse;\n"
    "            s += (att * pow(ndh, u_shininess)) * u_light_color[i] * u_specular;\n"
    "        }\n"
    "    }\n"
    "#endif\n"
    "#if TEXTURED\n"
    "    vec4 t = texture(u_tex, v_uv);\n"
    "#if SPECULAR_TEXTURE\n"
    "    gl_FragColor = vec4((d + s) * t.rgb, t.a);\n"
    "#else\n"
    "    gl_FragColor = vec4(d * t.rgb + s, t.a);\n"
    "#endif\n"
    "#else\n"
    "    gl_FragColor = vec4(d + s, 1.0);\n"
    "#endif\n"
    "#endif\n"
    "}\n";

static GLuint compile(GLenum type, const char *defines, const char *src, char *err, size_t err_size)
{
    GLuint sh = glCreateShader(type);
    /* #version must come first: the defines follow it. */
    const char *nl = strchr(src, '\n') + 1;
    char version[32];
    snprintf(version, sizeof version, "%.*s", (int)(nl - src), src);
    const char *parts[3] = {version, defines, nl};
    glShaderSource(sh, 3, parts, NULL);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        glGetShaderInfoLog(sh, sizeof log, NULL, log);
        snprintf(err, err_size, "peer: shader does not compile: %s", log);
        glDeleteShader(sh);
        return 0;
    }
    return sh;
}

/* The program for one material kind (textured, modulate, specular
 * texture), built on first use. */
static int get_program(bench_peer *p, const persp_scene_material *m, char *err, size_t err_size)
{
    int textured = m->texture >= 0, modulate = m->env == PERSP_SCENE_TEXENV_MODULATE;
    int spec_tex = textured && modulate && m->specular_texture;
    int key = textured | (modulate << 1) | (spec_tex << 2);
    if (p->programs[key].name) return key;
    char defines[256];
    snprintf(defines, sizeof defines,
             "#define NUM_LIGHTS %d\n#define TEXTURED %d\n#define MODULATE %d\n"
             "#define SPECULAR_TEXTURE %d\n#define NORMAL_QUALIFIER %s\n",
             p->light_count, textured, modulate, spec_tex, p->noperspective ? "noperspective" : "smooth");
    GLuint vs = compile(GL_VERTEX_SHADER, defines, vertex_src, err, err_size);
    if (!vs) return -1;
    GLuint fs = compile(GL_FRAGMENT_SHADER, defines, fragment_src, err, err_size);
    if (!fs) {
        glDeleteShader(vs);
        return -1;
    }
    GLuint prog = glCreateProgram();
    glAttachShader(prog, vs);
    glAttachShader(prog, fs);
    glBindAttribLocation(prog, 0, "a_pos");
    glBindAttribLocation(prog, 1, "a_normal");
    glBindAttribLocation(prog, 2, "a_uv");
    glLinkProgram(prog);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[512] = "";
        glGetProgramInfoLog(prog, sizeof log, NULL, log);
        snprintf(err, err_size, "peer: shader program does not link: %s", log);
        glDeleteProgram(prog);
        return -1;
    }
    glUseProgram(prog);
    if (p->light_count > 0) {
        glUniform4fv(glGetUniformLocation(prog, "u_light_pos"), p->light_count, &p->light_pos[0][0]);
        glUniform3fv(glGetUniformLocation(prog, "u_light_color"), p->light_count, &p->light_color[0][0]);
        glUniform3fv(glGetUniformLocation(prog, "u_light_atten"), p->light_count, &p->light_atten[0][0]);
    }
    if (textured) glUniform1i(glGetUniformLocation(prog, "u_tex"), 0);
    peer_program *pp = &p->programs[key];
    pp->name = prog;
    pp->mvp = glGetUniformLocation(prog, "u_mvp");
    pp->mv = glGetUniformLocation(prog, "u_mv");
    pp->nm = glGetUniformLocation(prog, "u_nm");
    pp->ambient = glGetUniformLocation(prog, "u_ambient");
    pp->diffuse = glGetUniformLocation(prog, "u_diffuse");
    pp->specular = glGetUniformLocation(prog, "u_specular");
    pp->shininess = glGetUniformLocation(prog, "u_shininess");
    return key;
}

/* --------------------------------------------------------------- objects */

/* Vertices as drawn: the mesh's own, or for flat shading one copy per
 * triangle corner carrying the face normal, so that GL_FLAT lights each
 * triangle with its plane's normal as persp does (GL 2.1 §2.14.7: a flat
 * primitive takes the provoking vertex's colour). */
static int build_buffers(bench_peer *p, const persp_scene_object *so, const float *uv, peer_object *o,
                         int colour_array, char *err, size_t err_size)
{
    size_t nv = p->flat ? so->index_count : so->vertex_count;
    float *buf = malloc((nv ? nv : 1) * VERTEX_FLOATS * sizeof(float));
    if (!buf) {
        snprintf(err, err_size, "peer: out of memory for %zu vertices", nv);
        return 0;
    }
    for (size_t i = 0; i < nv; i++) {
        const persp_vertex *v = &so->vertices[p->flat ? so->indices[i] : i];
        float *out = buf + i * VERTEX_FLOATS;
        memcpy(out, v->pos, 3 * sizeof(float));
        memcpy(out + 3, v->normal, 3 * sizeof(float));
        memcpy(out + 6, uv + 2 * (p->flat ? so->indices[i] : i), 2 * sizeof(float));
        /* Unlit, untextured: persp shows the vertex colour times the
         * material's diffuse colour. */
        for (int c = 0; c < 3; c++) out[8 + c] = v->color[c] * so->material.diffuse[c];
        out[11] = v->color[3];
    }
    if (p->flat) {
        for (size_t t = 0; t + 2 < nv; t += 3) {
            float *a = buf + t * VERTEX_FLOATS, *b = a + VERTEX_FLOATS, *c = b + VERTEX_FLOATS;
            float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                          e1[0] * e2[1] - e1[1] * e2[0]};
            for (int k = 0; k < 3; k++) memcpy(a + 3 + k * VERTEX_FLOATS, n, sizeof n);
        }
    }
    glGenVertexArrays(1, &o->vao);
    glBindVertexArray(o->vao);
    glGenBuffers(1, &o->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, o->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(nv * VERTEX_FLOATS * sizeof(float)), buf, GL_STATIC_DRAW);
    free(buf);
    const GLsizei stride = VERTEX_FLOATS * sizeof(float);
    if (p->path == PATH_GLSL) {
        glEnableVertexAttribArray(0);
        glEnableVertexAttribArray(1);
        glEnableVertexAttribArray(2);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, (const void *)0);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, (const void *)(3 * sizeof(float)));
        glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride, (const void *)(6 * sizeof(float)));
    } else {
        glEnableClientState(GL_VERTEX_ARRAY);
        glVertexPointer(3, GL_FLOAT, stride, (const void *)0);
        glEnableClientState(GL_NORMAL_ARRAY);
        glNormalPointer(GL_FLOAT, stride, (const void *)(3 * sizeof(float)));
        glEnableClientState(GL_TEXTURE_COORD_ARRAY);
        glTexCoordPointer(2, GL_FLOAT, stride, (const void *)(6 * sizeof(float)));
        if (colour_array) {
            glEnableClientState(GL_COLOR_ARRAY);
            glColorPointer(4, GL_FLOAT, stride, (const void *)(8 * sizeof(float)));
        }
    }
    o->indexed = !p->flat;
    if (p->flat) {
        o->count = (GLsizei)nv;
    } else {
        glGenBuffers(1, &o->ibo);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, o->ibo);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(so->index_count * sizeof(uint32_t)),
                     so->indices, GL_STATIC_DRAW);
        o->count = (GLsizei)so->index_count;
    }
    glBindVertexArray(0);
    return 1;
}

/* ----------------------------------------------------------------- setup */

/* The GL pipeline standing in for a persp shading mode. */
static void choose_pipeline(bench_peer *p, persp_shading shading)
{
    switch (shading) {
    case PERSP_SHADING_NONE: p->path = PATH_UNLIT; break;
    case PERSP_SHADING_FLAT:
    case PERSP_SHADING_GOURAUD:
    case PERSP_SHADING_GOURAUD_PC: p->path = PATH_FIXED; break;
    default: p->path = PATH_GLSL; break;
    }
    p->flat = shading == PERSP_SHADING_FLAT;
    /* Screen-linear normal schemes: the normal interpolated without
     * perspective division (GLSL 1.30 §4.3.9, noperspective). */
    p->noperspective = shading == PERSP_SHADING_PHONG || shading == PERSP_SHADING_PHONG_SLERP_SCREEN;
    switch (shading) {
    case PERSP_SHADING_NONE: p->pipeline = "no lighting, GL_REPLACE (untextured: vertex colour)"; break;
    case PERSP_SHADING_FLAT:
        p->pipeline = "fixed-function lighting, GL_FLAT face normals, GL_MODULATE, "
                      "GL_SEPARATE_SPECULAR_COLOR";
        break;
    case PERSP_SHADING_GOURAUD:
    case PERSP_SHADING_GOURAUD_PC:
        p->pipeline = "fixed-function lighting, GL_SMOOTH, GL_MODULATE, GL_SINGLE_COLOR";
        break;
    default:
        p->pipeline = p->noperspective ? "GLSL Blinn-Phong per fragment, noperspective normals"
                                       : "GLSL Blinn-Phong per fragment";
        break;
    }
}

/* An OSMesa context drawing into p->color, made current. */
static int open_context(bench_peer *p, char *err, size_t err_size)
{
    /* 24-bit depth: what a default GL visual gives; persp keeps float depth. */
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                           OSMESA_PROFILE, OSMESA_COMPAT_PROFILE, 0};
    p->gl = OSMesaCreateContextAttribs(attribs, NULL);
    if (!p->gl) {
        snprintf(err, err_size, "peer: OSMesa could not create a context (GALLIUM_DRIVER=%s)",
                 getenv("GALLIUM_DRIVER") ? getenv("GALLIUM_DRIVER") : "");
        return 0;
    }
    p->color = malloc((size_t)p->width * (size_t)p->height * 4);
    if (!p->color) {
        snprintf(err, err_size, "peer: out of memory for a %dx%d image", p->width, p->height);
        return 0;
    }
    if (!OSMesaMakeCurrent(p->gl, p->color, GL_UNSIGNED_BYTE, p->width, p->height)) {
        snprintf(err, err_size, "peer: OSMesaMakeCurrent failed for %dx%d", p->width, p->height);
        return 0;
    }
    const char *s = (const char *)glGetString(GL_RENDERER);
    snprintf(p->renderer, sizeof p->renderer, "%s", s ? s : "?");
    s = (const char *)glGetString(GL_VERSION);
    snprintf(p->version, sizeof p->version, "%s", s ? s : "?");
    return 1;
}

/* Lights in eye space, as persp_render places them (directions
 * normalised; GL 2.1 §2.14.1 uses unit vectors too). */
static void eye_space_lights(bench_peer *p, const persp_scene *scene, persp_mat4 view)
{
    size_t nl = persp_scene_light_count(scene);
    if (nl > 8) nl = 8;
    p->light_count = (int)nl;
    for (size_t i = 0; i < nl; i++) {
        persp_scene_light l;
        persp_scene_get_light(scene, i, &l);
        persp_vec4 e = persp_mat4_apply(view, (persp_vec4){l.position[0], l.position[1], l.position[2],
                                                           l.directional ? 0.0f : 1.0f});
        float w = l.directional ? 0.0f : 1.0f;
        if (l.directional) {
            float len = sqrtf(e.x * e.x + e.y * e.y + e.z * e.z);
            if (len > 0.0f) e.x /= len, e.y /= len, e.z /= len;
        }
        p->light_pos[i][0] = e.x, p->light_pos[i][1] = e.y, p->light_pos[i][2] = e.z;
        p->light_pos[i][3] = w;
        memcpy(p->light_color[i], l.color, sizeof l.color);
        if (l.directional) {
            p->light_atten[i][0] = 1.0f, p->light_atten[i][1] = 0.0f, p->light_atten[i][2] = 0.0f;
        } else {
            memcpy(p->light_atten[i], l.attenuation, sizeof l.attenuation);
        }
    }
}

/* State shared by every path: viewport, depth test, clear colour, culling. */
static void set_common_state(const bench_peer *p, const persp_scene_info *info)
{
    glViewport(0, 0, p->width, p->height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glClearDepth(1.0);
    glClearColor(p->clear[0], p->clear[1], p->clear[2], p->clear[3]);
    if (info->cull_backfaces) {
        glEnable(GL_CULL_FACE);
        glCullFace(GL_BACK);
        glFrontFace(GL_CCW);
    } else {
        glDisable(GL_CULL_FACE);
    }
    glDisable(GL_DITHER);
    glDisable(GL_BLEND);
}

/* The fixed-function lighting model and lights (PATH_FIXED). */
static void set_fixed_lighting(const bench_peer *p, const persp_scene *scene, persp_mat4 view)
{
    /* Lights are stored in eye space by the modelview matrix current
     * when glLightfv sets their position (GL 2.1 §2.14.2). */
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixf(view.m);
    glEnable(GL_LIGHTING);
    glEnable(GL_NORMALIZE);
    glShadeModel(p->flat ? GL_FLAT : GL_SMOOTH);
    const float amb[4] = {p->ambient[0], p->ambient[1], p->ambient[2], 1.0f};
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, amb);
    /* persp lights with the view vector of each point (a local viewer)
     * and both faces of a polygon (GL 2.1 §2.14.1, Table 2.10). */
    glLightModeli(GL_LIGHT_MODEL_LOCAL_VIEWER, GL_TRUE);
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
    for (int i = 0; i < p->light_count; i++) {
        const float zero[4] = {0, 0, 0, 1};
        persp_scene_light l;
        persp_scene_get_light(scene, (size_t)i, &l);
        float pos[4] = {l.position[0], l.position[1], l.position[2], l.directional ? 0.0f : 1.0f};
        float col[4] = {l.color[0], l.color[1], l.color[2], 1.0f};
        GLenum L = GL_LIGHT0 + (GLenum)i;
        glEnable(L);
        glLightfv(L, GL_POSITION, pos);
        glLightfv(L, GL_AMBIENT, zero);
        glLightfv(L, GL_DIFFUSE, col);
        glLightfv(L, GL_SPECULAR, col);
        glLightf(L, GL_CONSTANT_ATTENUATION, p->light_atten[i][0]);
        glLightf(L, GL_LINEAR_ATTENUATION, p->light_atten[i][1]);
        glLightf(L, GL_QUADRATIC_ATTENUATION, p->light_atten[i][2]);
    }
}

/* The object table and one texture slot per scene texture used. */
static int alloc_tables(bench_peer *p, const persp_scene *scene, char *err, size_t err_size)
{
    size_t nobj = persp_scene_object_count(scene);
    p->objects = calloc(nobj ? nobj : 1, sizeof *p->objects);
    p->texture_count = 0;
    for (size_t i = 0; i < nobj; i++) {
        persp_scene_object so;
        persp_scene_get_object(scene, i, &so);
        if (so.material.texture >= 0 && (size_t)so.material.texture + 1 > p->texture_count)
            p->texture_count = (size_t)so.material.texture + 1;
    }
    p->textures = calloc(p->texture_count ? p->texture_count : 1, sizeof *p->textures);
    if (!p->objects || !p->textures) {
        snprintf(err, err_size, "peer: out of memory");
        return 0;
    }
    return 1;
}

/* Scene object i as drawn: matrices, texture and sampler, buffers and
 * (PATH_GLSL) program. Counted in p->object_count before anything is made,
 * so bench_peer_destroy frees what a failure leaves behind. */
static int add_object(bench_peer *p, const bench_peer_desc *desc, size_t i, persp_mat4 view,
                      persp_mat4 proj, char *err, size_t err_size)
{
    const persp_scene *scene = desc->scene;
    persp_scene_object so;
    persp_scene_get_object(scene, i, &so);
    peer_object *o = &p->objects[p->object_count++];
    o->mat = so.material;
    o->mirrored = persp_mat4_det3(so.model) < 0.0;
    persp_mat4 mv = persp_mat4_mul(view, so.model), mvp = persp_mat4_mul(proj, mv);
    memcpy(o->mv, mv.m, sizeof o->mv);
    memcpy(o->mvp, mvp.m, sizeof o->mvp);
    if (!persp_mat4_normal_matrix(mv, o->nm)) memset(o->nm, 0, sizeof o->nm);
    int textured = so.material.texture >= 0;
    if (textured) {
        GLuint *t = &p->textures[so.material.texture];
        if (!*t && !upload_texture(persp_scene_get_texture(scene, so.material.texture), t, err, err_size))
            return 0;
        o->texture = *t;
        if (!make_sampler(p, desc, &so.material.sampler, &o->sampler, err, err_size)) return 0;
    }
    /* The coordinates persp draws with: its texgen applied (the
     * reflection map for this camera). */
    float *uv = malloc((so.vertex_count ? so.vertex_count : 1) * 2 * sizeof(float));
    if (!uv) {
        snprintf(err, err_size, "peer: out of memory for %zu vertices", so.vertex_count);
        return 0;
    }
    persp_scene_object_texcoords(scene, i, &view, uv);
    const int built = build_buffers(p, &so, uv, o, p->path == PATH_UNLIT && !textured, err, err_size);
    free(uv);
    if (!built) return 0;
    if (p->path == PATH_GLSL && (o->program = get_program(p, &so.material, err, err_size)) < 0) return 0;
    return 1;
}

/* GL state, lights and every object; 0 with err set on failure. */
static int build_scene(bench_peer *p, const bench_peer_desc *desc, const persp_scene_info *info,
                       char *err, size_t err_size)
{
    const persp_scene *scene = desc->scene;
    persp_mat4 proj, view;
    persp_scene_get_camera(scene, p->width, p->height, &view, &proj);
    for (int c = 0; c < 4; c++) p->clear[c] = (float)info->clear[c] / 255.0f;
    memcpy(p->ambient, info->ambient, sizeof p->ambient);
    eye_space_lights(p, scene, view);

    set_common_state(p, info);
    if (p->path == PATH_FIXED) set_fixed_lighting(p, scene, view);
    glMatrixMode(GL_PROJECTION);
    glLoadMatrixf(proj.m);
    glMatrixMode(GL_MODELVIEW);

    if (!alloc_tables(p, scene, err, err_size)) return 0;
    size_t nobj = persp_scene_object_count(scene);
    for (size_t i = 0; i < nobj; i++)
        if (!add_object(p, desc, i, view, proj, err, err_size)) return 0;
    glUseProgram(0);

    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        snprintf(err, err_size, "peer: OpenGL error 0x%04x while setting up", (unsigned)e);
        return 0;
    }
    return 1;
}

bench_peer *bench_peer_create(const bench_peer_desc *desc, char *err, size_t err_size)
{
    if (!desc || desc->width < 1 || desc->height < 1 || !desc->scene) {
        snprintf(err, err_size, "peer: bad image size or no scene");
        return NULL;
    }
    if (!bench_peer_supports(desc->filter)) {
        snprintf(err, err_size, "peer: filter '%s' has no OpenGL counterpart",
                 persp_filter_name(desc->filter));
        return NULL;
    }
    persp_scene_info info;
    persp_scene_get_info(desc->scene, &info);
    persp_shading shading = desc->shading != PERSP_SHADING_DEFAULT ? desc->shading : info.shading;

    bench_peer *p = calloc(1, sizeof *p);
    if (!p) {
        snprintf(err, err_size, "peer: out of memory");
        return NULL;
    }
    p->width = desc->width;
    p->height = desc->height;
    choose_pipeline(p, shading);
    /* bench_peer_destroy frees whatever part was made, context or none. */
    if (!open_context(p, err, err_size) || !build_scene(p, desc, &info, err, err_size)) {
        bench_peer_destroy(p);
        return NULL;
    }
    return p;
}

static void draw_fixed(bench_peer *p, const peer_object *o)
{
    const persp_scene_material *m = &o->mat;
    int textured = o->texture != 0, modulate = m->env == PERSP_SCENE_TEXENV_MODULATE;
    glLoadMatrixf(o->mv);
    if (p->path == PATH_FIXED) {
        /* An unlit material (persp draws it unlit in every mode) is its
         * diffuse colour as emission with no other term. */
        const float lit = m->unlit ? 0.0f : 1.0f;
        float a[4] = {lit * m->ambient[0], lit * m->ambient[1], lit * m->ambient[2], 1.0f};
        float d[4] = {lit * m->diffuse[0], lit * m->diffuse[1], lit * m->diffuse[2], 1.0f};
        float e[4] = {m->unlit ? m->diffuse[0] : m->emission[0], m->unlit ? m->diffuse[1] : m->emission[1],
                      m->unlit ? m->diffuse[2] : m->emission[2], 1.0f};
        /* persp leaves out the specular term at shininess 0, where GL's
         * (N·H)^0 would be 1; GL limits the exponent to 128 (§2.14.1). */
        float sc = m->shininess > 0.0f ? lit : 0.0f;
        float s[4] = {sc * m->specular[0], sc * m->specular[1], sc * m->specular[2], 1.0f};
        glMaterialfv(GL_FRONT_AND_BACK, GL_EMISSION, e);
        glMaterialfv(GL_FRONT_AND_BACK, GL_AMBIENT, a);
        glMaterialfv(GL_FRONT_AND_BACK, GL_DIFFUSE, d);
        glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, s);
        glMaterialf(GL_FRONT_AND_BACK, GL_SHININESS, m->shininess < 128.0f ? m->shininess : 128.0f);
        /* Flat: persp modulates ambient + diffuse and adds the specular
         * term after texturing, the colour sum of GL 2.1 §3.10; Gouraud
         * lights each vertex with all three terms and modulates the sum,
         * GL's single colour. A specular texture modulates both. */
        int separate = p->flat && textured && modulate && !m->specular_texture;
        glLightModeli(GL_LIGHT_MODEL_COLOR_CONTROL, separate ? GL_SEPARATE_SPECULAR_COLOR : GL_SINGLE_COLOR);
    }
    if (textured) {
        glEnable(GL_TEXTURE_2D);
        glBindTexture(GL_TEXTURE_2D, o->texture);
        glBindSampler(0, o->sampler);
        /* Unlit, an unlit material's colour tints its texels (the current
         * colour: this path binds no colour array to textured objects). */
        const int tint = p->path == PATH_UNLIT && m->unlit && modulate;
        if (tint) glColor4f(m->diffuse[0], m->diffuse[1], m->diffuse[2], 1.0f);
        glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE,
                  (p->path == PATH_FIXED && modulate) || tint ? GL_MODULATE : GL_REPLACE);
    } else {
        glDisable(GL_TEXTURE_2D);
    }
}

static void draw_glsl(bench_peer *p, const peer_object *o)
{
    const peer_program *pp = &p->programs[o->program];
    const persp_scene_material *m = &o->mat;
    glUseProgram(pp->name);
    glUniformMatrix4fv(pp->mvp, 1, GL_FALSE, o->mvp);
    glUniformMatrix4fv(pp->mv, 1, GL_FALSE, o->mv);
    glUniformMatrix3fv(pp->nm, 1, GL_FALSE, o->nm);
    /* Emission joins the ambient term, as in persp's lighting; an unlit
     * material is its diffuse colour alone. */
    const float lit = m->unlit ? 0.0f : 1.0f;
    float a[3], d[3];
    for (int c = 0; c < 3; c++) {
        a[c] = m->unlit ? m->diffuse[c] : p->ambient[c] * m->ambient[c] + m->emission[c];
        d[c] = lit * m->diffuse[c];
    }
    float sc = m->shininess > 0.0f ? lit : 0.0f;
    float s[3] = {sc * m->specular[0], sc * m->specular[1], sc * m->specular[2]};
    glUniform3fv(pp->ambient, 1, a);
    glUniform3fv(pp->diffuse, 1, d);
    glUniform3fv(pp->specular, 1, s);
    glUniform1f(pp->shininess, m->shininess);
    if (o->texture) {
        glBindTexture(GL_TEXTURE_2D, o->texture);
        glBindSampler(0, o->sampler);
    }
}

void bench_peer_render(bench_peer *p, int frames)
{
    for (int f = 0; f < frames; f++) {
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        for (size_t i = 0; i < p->object_count; i++) {
            const peer_object *o = &p->objects[i];
            /* persp culls a mirrored object's counter-clockwise faces. */
            glFrontFace(o->mirrored ? GL_CW : GL_CCW);
            if (p->path == PATH_GLSL)
                draw_glsl(p, o);
            else
                draw_fixed(p, o);
            glBindVertexArray(o->vao);
            if (o->indexed)
                glDrawElements(GL_TRIANGLES, o->count, GL_UNSIGNED_INT, (const void *)0);
            else
                glDrawArrays(GL_TRIANGLES, 0, o->count);
        }
        glBindVertexArray(0);
        /* Each frame complete before the next, as persp_render's are. */
        glFinish();
    }
}

const uint8_t *bench_peer_pixels(const bench_peer *p) { return p->color; }
const char *bench_peer_renderer(const bench_peer *p) { return p->renderer; }
const char *bench_peer_version(const bench_peer *p) { return p->version; }
float bench_peer_aniso(const bench_peer *p) { return p->aniso; }
const char *bench_peer_pipeline(const bench_peer *p) { return p->pipeline; }

void bench_peer_destroy(bench_peer *p)
{
    if (!p) return;
    if (p->gl) {
        for (size_t i = 0; i < p->object_count; i++) {
            peer_object *o = &p->objects[i];
            if (o->vao) glDeleteVertexArrays(1, &o->vao);
            if (o->vbo) glDeleteBuffers(1, &o->vbo);
            if (o->ibo) glDeleteBuffers(1, &o->ibo);
            if (o->sampler) glDeleteSamplers(1, &o->sampler);
        }
        for (size_t i = 0; i < p->texture_count; i++)
            if (p->textures && p->textures[i]) glDeleteTextures(1, &p->textures[i]);
        for (int i = 0; i < MAX_PROGRAMS; i++)
            if (p->programs[i].name) glDeleteProgram(p->programs[i].name);
        /* Unbinding first lets OSMesa release the framebuffer it made for us. */
        OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
        OSMesaDestroyContext(p->gl);
    }
    free(p->objects);
    free(p->textures);
    free(p->color);
    free(p);
}
