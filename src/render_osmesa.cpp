// This file is part of OpenCV project.
// It is subject to the license terms in the LICENSE file found in the top-level directory
// of this distribution and at http://opencv.org/license.html

// Renderer: OSMesa (llvmpipe) off-screen OpenGL 3.3 core context, one FBO with a colour
// attachment (RGB + label in alpha), a float attachment holding the camera z of the surface and
// a depth renderbuffer for the z-test. Projection straight from the OpenCV intrinsics.

#include "precomp.hpp"

#ifdef HAVE_OSMESA
// libOSMesa exports the GL entry points itself (nm -D): no loader needed.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/osmesa.h>
#include <GL/gl.h>
#include <GL/glext.h>
#endif

namespace cv {
namespace forestmod {

Renderer::~Renderer()
{
}

#ifdef HAVE_OSMESA

namespace {

const char* kVertexShader = R"GLSL(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_color;
uniform mat3 u_R;
uniform vec3 u_t;
uniform mat4 u_projection;
out vec3 v_position;
out vec3 v_normal;
out vec3 v_color;
void main()
{
    vec3 p = u_R * a_position + u_t;
    v_position = p;
    v_normal = u_R * a_normal;
    v_color = a_color;
    gl_Position = u_projection * vec4(p, 1.0);
}
)GLSL";

const char* kFragmentShader = R"GLSL(#version 330 core
in vec3 v_position;
in vec3 v_normal;
in vec3 v_color;
uniform float u_ambient;
uniform float u_label;
layout(location = 0) out vec4 o_color;
layout(location = 1) out float o_z;
void main()
{
    vec3 l = normalize(-v_position);
    float len = length(v_normal);
    float diffuse = len > 1e-12 ? abs(dot(v_normal / len, l)) : 1.0;
    o_color = vec4(v_color * (u_ambient + (1.0 - u_ambient) * diffuse), u_label);
    o_z = v_position.z;
}
)GLSL";

struct GpuMesh
{
    GLuint vao, vbo, ebo;
    GLsizei num_indices;
    Point3f corners[8]; // bounding box corners, for the near/far planes
};

class RendererImpl CV_FINAL : public Renderer
{
public:
    explicit RendererImpl(Size size);
    ~RendererImpl() CV_OVERRIDE;

    Size size() const CV_OVERRIDE { return size_; }
    int addMesh(const Mesh& mesh) CV_OVERRIDE;
    int numMeshes() const CV_OVERRIDE { return (int)meshes_.size(); }
    void setAmbient(double ambient) CV_OVERRIDE
    {
        CV_Check(ambient, ambient >= 0 && ambient <= 1, "Renderer::setAmbient: must be in [0, 1]");
        ambient_ = ambient;
    }
    double getAmbient() const CV_OVERRIDE { return ambient_; }
    void render(int handle, const Matx33d& R, const Vec3d& t, const Matx33d& K, OutputArray color,
                OutputArray depth, OutputArray mask) CV_OVERRIDE;
    void renderScene(const std::vector<int>& handles, const std::vector<Matx33d>& R,
                     const std::vector<Vec3d>& t, const Matx33d& K, OutputArray color,
                     OutputArray depth, OutputArray labels) CV_OVERRIDE;

private:
    void makeCurrent();
    void checkGL(const char* where);
    GLuint compile(GLenum type, const char* src);
    void checkDraw(const std::vector<int>& handles, const std::vector<Matx33d>& R,
                   const std::vector<Vec3d>& t, const Matx33d& K, const char* fn);
    Rect drawRegion(const std::vector<int>& handles, const std::vector<Matx33d>& R,
                    const std::vector<Vec3d>& t, const Matx33d& K, double& znear,
                    double& zfar) const;
    void rasterize(const std::vector<int>& handles, const std::vector<Matx33d>& R,
                   const std::vector<Vec3d>& t, const Matx33d& K, bool single, Rect roi,
                   double znear, double zfar, const char* fn);
    void readOutputs(Rect roi, bool single, OutputArray color, OutputArray depth,
                     OutputArray third);
    void draw(const std::vector<int>& handles, const std::vector<Matx33d>& R,
              const std::vector<Vec3d>& t, const Matx33d& K, bool single, OutputArray color,
              OutputArray depth, OutputArray third);

    Size size_;
    OSMesaContext ctx_;
    std::vector<uchar> buffer_; // OSMesa's own framebuffer (unused: we draw into the FBO)
    GLuint fbo_, color_rb_, z_rb_, depth_rb_, program_;
    GLint loc_R_, loc_t_, loc_projection_, loc_ambient_, loc_label_;
    std::vector<GpuMesh> meshes_;
    double ambient_;
    Mutex mutex_;
    Mat bgra_, z_; // read-back buffers
};

RendererImpl::RendererImpl(Size size)
    : size_(size), ctx_(0), fbo_(0), color_rb_(0), z_rb_(0), depth_rb_(0), program_(0), loc_R_(-1),
      loc_t_(-1), loc_projection_(-1), loc_ambient_(-1), loc_label_(-1), ambient_(0.3)
{
    if (size.width <= 0 || size.height <= 0)
        CV_Error_(Error::StsBadArg,
                  ("Renderer::create: the image size must be positive, got %dx%d", size.width,
                   size.height));
    const int attribs[] = { OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                            OSMESA_STENCIL_BITS, 0, OSMESA_ACCUM_BITS, 0,
                            OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3,
                            0 };
    ctx_ = OSMesaCreateContextAttribs(attribs, NULL);
    if (!ctx_)
        CV_Error(Error::StsError,
                 "Renderer::create: OSMesaCreateContextAttribs failed (no OpenGL 3.3 core profile "
                 "from OSMesa)");
    buffer_.resize((size_t)size.width * size.height * 4);
    try
    {
        makeCurrent();
        GLint max_rb = 0;
        glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_rb);
        if (size.width > max_rb || size.height > max_rb)
            CV_Error_(Error::StsBadArg,
                      ("Renderer::create: %dx%d exceeds the largest OpenGL render buffer (%d)",
                       size.width, size.height, (int)max_rb));

        GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
        GLuint fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
        program_ = glCreateProgram();
        glAttachShader(program_, vs);
        glAttachShader(program_, fs);
        glLinkProgram(program_);
        glDeleteShader(vs);
        glDeleteShader(fs);
        GLint ok = 0;
        glGetProgramiv(program_, GL_LINK_STATUS, &ok);
        if (!ok)
        {
            char log[2048] = { 0 };
            glGetProgramInfoLog(program_, sizeof(log) - 1, NULL, log);
            CV_Error_(Error::StsError, ("Renderer: shader link failed: %s", log));
        }
        loc_R_ = glGetUniformLocation(program_, "u_R");
        loc_t_ = glGetUniformLocation(program_, "u_t");
        loc_projection_ = glGetUniformLocation(program_, "u_projection");
        loc_ambient_ = glGetUniformLocation(program_, "u_ambient");
        loc_label_ = glGetUniformLocation(program_, "u_label");

        glGenFramebuffers(1, &fbo_);
        glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
        glGenRenderbuffers(1, &color_rb_);
        glBindRenderbuffer(GL_RENDERBUFFER, color_rb_);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, size.width, size.height);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_rb_);
        glGenRenderbuffers(1, &z_rb_);
        glBindRenderbuffer(GL_RENDERBUFFER, z_rb_);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_R32F, size.width, size.height);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, z_rb_);
        glGenRenderbuffers(1, &depth_rb_);
        glBindRenderbuffer(GL_RENDERBUFFER, depth_rb_);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, size.width, size.height);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb_);
        const GLenum draw_buffers[2] = { GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1 };
        glDrawBuffers(2, draw_buffers);
        const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
        if (status != GL_FRAMEBUFFER_COMPLETE)
            CV_Error_(Error::StsError, ("Renderer: framebuffer incomplete (0x%x)", (unsigned)status));
        glViewport(0, 0, size.width, size.height);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDisable(GL_CULL_FACE); // meshes with inconsistent winding render fully
        glDisable(GL_BLEND);
        glDisable(GL_DITHER);
        glPixelStorei(GL_PACK_ALIGNMENT, 1);
        checkGL("Renderer::create");
    }
    catch (...)
    {
        OSMesaDestroyContext(ctx_);
        ctx_ = 0;
        throw;
    }
}

RendererImpl::~RendererImpl()
{
    if (!ctx_)
        return;
    if (OSMesaMakeCurrent(ctx_, &buffer_[0], GL_UNSIGNED_BYTE, size_.width, size_.height))
    {
        for (size_t i = 0; i < meshes_.size(); ++i)
        {
            glDeleteVertexArrays(1, &meshes_[i].vao);
            glDeleteBuffers(1, &meshes_[i].vbo);
            glDeleteBuffers(1, &meshes_[i].ebo);
        }
        glDeleteRenderbuffers(1, &color_rb_);
        glDeleteRenderbuffers(1, &z_rb_);
        glDeleteRenderbuffers(1, &depth_rb_);
        glDeleteFramebuffers(1, &fbo_);
        glDeleteProgram(program_);
    }
    OSMesaMakeCurrent(NULL, NULL, 0, 0, 0);
    OSMesaDestroyContext(ctx_);
}

void RendererImpl::makeCurrent()
{
    if (OSMesaGetCurrentContext() == ctx_)
        return;
    if (!OSMesaMakeCurrent(ctx_, &buffer_[0], GL_UNSIGNED_BYTE, size_.width, size_.height))
        CV_Error(Error::StsError, "Renderer: OSMesaMakeCurrent failed");
}

void RendererImpl::checkGL(const char* where)
{
    const GLenum err = glGetError();
    if (err != GL_NO_ERROR)
        CV_Error_(Error::StsError, ("%s: OpenGL error 0x%x", where, (unsigned)err));
}

GLuint RendererImpl::compile(GLenum type, const char* src)
{
    GLuint shader = glCreateShader(type);
    glShaderSource(shader, 1, &src, NULL);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok)
    {
        char log[2048] = { 0 };
        glGetShaderInfoLog(shader, sizeof(log) - 1, NULL, log);
        glDeleteShader(shader);
        CV_Error_(Error::StsError, ("Renderer: shader compilation failed: %s", log));
    }
    return shader;
}

int RendererImpl::addMesh(const Mesh& mesh_in)
{
    mesh_in.validate();
    AutoLock lock(mutex_);
    const Mesh* mesh = &mesh_in;
    Mesh completed;
    if (mesh_in.normals.empty())
    {
        completed = mesh_in;
        completed.computeNormals();
        mesh = &completed;
    }
    const size_t n = mesh->vertices.size();
    std::vector<float> data(n * 9);
    for (size_t i = 0; i < n; ++i)
    {
        float* d = &data[i * 9];
        d[0] = mesh->vertices[i].x;
        d[1] = mesh->vertices[i].y;
        d[2] = mesh->vertices[i].z;
        d[3] = mesh->normals[i][0];
        d[4] = mesh->normals[i][1];
        d[5] = mesh->normals[i][2];
        const Vec3b c = mesh->colors.empty() ? Vec3b(128, 128, 128) : mesh->colors[i];
        d[6] = c[2] / 255.f; // BGR -> RGB
        d[7] = c[1] / 255.f;
        d[8] = c[0] / 255.f;
    }
    std::vector<GLuint> indices(mesh->faces.size() * 3);
    for (size_t f = 0; f < mesh->faces.size(); ++f)
        for (int k = 0; k < 3; ++k)
            indices[f * 3 + k] = (GLuint)mesh->faces[f][k];

    makeCurrent();
    GpuMesh g;
    glGenVertexArrays(1, &g.vao);
    glBindVertexArray(g.vao);
    glGenBuffers(1, &g.vbo);
    glBindBuffer(GL_ARRAY_BUFFER, g.vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(data.size() * sizeof(float)), &data[0],
                 GL_STATIC_DRAW);
    glGenBuffers(1, &g.ebo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g.ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(indices.size() * sizeof(GLuint)),
                 &indices[0], GL_STATIC_DRAW);
    const GLsizei stride = 9 * sizeof(float);
    for (GLuint a = 0; a < 3; ++a)
    {
        glEnableVertexAttribArray(a);
        glVertexAttribPointer(a, 3, GL_FLOAT, GL_FALSE, stride,
                              reinterpret_cast<const void*>(a * 3 * sizeof(float)));
    }
    glBindVertexArray(0);
    g.num_indices = (GLsizei)indices.size();
    const Point3f lo = mesh->bboxMin(), hi = mesh->bboxMax();
    for (int c = 0; c < 8; ++c)
        g.corners[c] = Point3f((c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z);
    checkGL("Renderer::addMesh");
    meshes_.push_back(g);
    return (int)meshes_.size() - 1;
}

void RendererImpl::render(int handle, const Matx33d& R, const Vec3d& t, const Matx33d& K,
                          OutputArray color, OutputArray depth, OutputArray mask)
{
    draw(std::vector<int>(1, handle), std::vector<Matx33d>(1, R), std::vector<Vec3d>(1, t), K,
         true, color, depth, mask);
}

void RendererImpl::renderScene(const std::vector<int>& handles, const std::vector<Matx33d>& R,
                               const std::vector<Vec3d>& t, const Matx33d& K, OutputArray color,
                               OutputArray depth, OutputArray labels)
{
    draw(handles, R, t, K, false, color, depth, labels);
}

static void checkPose(const Matx33d& R, const Vec3d& t, int index)
{
    for (int i = 0; i < 9; ++i)
        if (!std::isfinite(R.val[i]))
            CV_Error_(Error::StsBadArg, ("Renderer: rotation %d is not finite", index));
    // tolerance: rotations stored with few digits (BOP's LM ground truth deviates by 2e-3)
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(t[i]))
            CV_Error_(Error::StsBadArg, ("Renderer: translation %d is not finite", index));
    const double err = norm(R * R.t() - Matx33d::eye(), NORM_INF);
    if (err > 1e-2 || determinant(R) < 0)
        CV_Error_(Error::StsBadArg,
                  ("Renderer: R[%d] is not a rotation (|R R^T - I| = %g, det = %g)", index, err,
                   determinant(R)));
}

void RendererImpl::checkDraw(const std::vector<int>& handles, const std::vector<Matx33d>& R,
                             const std::vector<Vec3d>& t, const Matx33d& K, const char* fn)
{
    if (handles.size() != R.size() || handles.size() != t.size())
        CV_Error_(Error::StsBadSize, ("%s: %d handles, %d rotations, %d translations", fn,
                                      (int)handles.size(), (int)R.size(), (int)t.size()));
    if (handles.size() > 255)
        CV_Error_(Error::StsOutOfRange, ("%s: at most 255 meshes per image, got %d", fn,
                                         (int)handles.size()));
    const double fx = K(0, 0), fy = K(1, 1), cx = K(0, 2), cy = K(1, 2);
    if (!(fx > 0) || !(fy > 0) || !std::isfinite(fx) || !std::isfinite(fy) || !std::isfinite(cx)
        || !std::isfinite(cy))
        CV_Error_(Error::StsBadArg, ("%s: K needs positive finite fx, fy and finite cx, cy (got "
                                     "%g, %g, %g, %g)", fn, fx, fy, cx, cy));
    if (K(0, 1) != 0 || K(1, 0) != 0 || K(2, 0) != 0 || K(2, 1) != 0 || K(2, 2) != 1)
        CV_Error_(Error::StsBadArg, ("%s: K must be [fx 0 cx; 0 fy cy; 0 0 1] (the renderer draws "
                                     "without skew), got K(0, 1) %g, K(1, 0) %g and last row (%g, "
                                     "%g, %g)", fn, K(0, 1), K(1, 0), K(2, 0), K(2, 1), K(2, 2)));
    for (size_t i = 0; i < handles.size(); ++i)
    {
        if (handles[i] < 0 || handles[i] >= (int)meshes_.size())
            CV_Error_(Error::StsOutOfRange, ("%s: handle %d unknown (%d meshes added)", fn,
                                             handles[i], (int)meshes_.size()));
        checkPose(R[i], t[i], (int)i);
    }
}

// Near/far from the bounding boxes (the float attachment holds the exact z, so the z-buffer only
// has to order the surfaces), and the image region where the boxes project: only it is cleared,
// drawn and read back (the rest is background). When every box corner is in front of the near
// plane, the projection of the corners bounds the projection of the meshes.
Rect RendererImpl::drawRegion(const std::vector<int>& handles, const std::vector<Matx33d>& R,
                              const std::vector<Vec3d>& t, const Matx33d& K, double& znear,
                              double& zfar) const
{
    double zmin = DBL_MAX, zmax = -DBL_MAX;
    double umin = DBL_MAX, umax = -DBL_MAX, vmin = DBL_MAX, vmax = -DBL_MAX;
    for (size_t i = 0; i < handles.size(); ++i)
        for (int c = 0; c < 8; ++c)
        {
            const Point3f& q = meshes_[handles[i]].corners[c];
            const Vec3d p = R[i] * Vec3d(q.x, q.y, q.z) + t[i];
            zmin = std::min(zmin, p[2]);
            zmax = std::max(zmax, p[2]);
            const double u = (K(0, 0) * p[0] + K(0, 1) * p[1]) / p[2] + K(0, 2);
            const double v = K(1, 1) * p[1] / p[2] + K(1, 2);
            umin = std::min(umin, u);
            umax = std::max(umax, u);
            vmin = std::min(vmin, v);
            vmax = std::max(vmax, v);
        }
    const int W = size_.width, H = size_.height;
    zfar = zmax * 1.01 + 1.0;
    znear = std::max(zmin * 0.99 - 1.0, zfar * 1e-5);
    if (handles.empty() || zmax <= 0)
        return Rect();
    if (!(zmin > znear))
        return Rect(0, 0, W, H);
    // clamped on both sides before the int conversion (far off-screen boxes)
    const double lo_u = std::min(W + 1.0, std::max(-1.0, std::floor(umin) - 1));
    const double hi_u = std::max(-1.0, std::min(W + 1.0, std::ceil(umax) + 2));
    const double lo_v = std::min(H + 1.0, std::max(-1.0, std::floor(vmin) - 1));
    const double hi_v = std::max(-1.0, std::min(H + 1.0, std::ceil(vmax) + 2));
    return Rect((int)lo_u, (int)lo_v, (int)std::max(0.0, hi_u - lo_u),
                (int)std::max(0.0, hi_v - lo_v)) & Rect(0, 0, W, H);
}

void RendererImpl::rasterize(const std::vector<int>& handles, const std::vector<Matx33d>& R,
                             const std::vector<Vec3d>& t, const Matx33d& K, bool single, Rect roi,
                             double znear, double zfar, const char* fn)
{
    const int W = size_.width, H = size_.height;
    makeCurrent();
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glEnable(GL_SCISSOR_TEST);
    glScissor(roi.x, roi.y, roi.width, roi.height); // no y flip: GL row = image row
    const GLfloat zero[4] = { 0.f, 0.f, 0.f, 0.f };
    const GLfloat one = 1.f;
    glClearBufferfv(GL_COLOR, 0, zero);
    glClearBufferfv(GL_COLOR, 1, zero);
    glClearBufferfv(GL_DEPTH, 0, &one);
    // OpenCV pixel (u, v) = GL window (u + 0.5, v + 0.5); no y flip, so that row v of the
    // read-back buffer is image row v (the winding flips, culling is off).
    Matx44f P = Matx44f::zeros();
    P(0, 0) = (float)(2.0 * K(0, 0) / W);
    P(0, 1) = (float)(2.0 * K(0, 1) / W);
    P(0, 2) = (float)(2.0 * (K(0, 2) + 0.5) / W - 1.0);
    P(1, 1) = (float)(2.0 * K(1, 1) / H);
    P(1, 2) = (float)(2.0 * (K(1, 2) + 0.5) / H - 1.0);
    P(2, 2) = (float)((zfar + znear) / (zfar - znear));
    P(2, 3) = (float)(-2.0 * zfar * znear / (zfar - znear));
    P(3, 2) = 1.f;
    glUseProgram(program_);
    glUniformMatrix4fv(loc_projection_, 1, GL_TRUE, P.val);
    glUniform1f(loc_ambient_, (float)ambient_);
    for (size_t i = 0; i < handles.size(); ++i)
    {
        const Matx33f Rf(R[i]);
        const Vec3f tf(t[i]);
        glUniformMatrix3fv(loc_R_, 1, GL_TRUE, Rf.val);
        glUniform3f(loc_t_, tf[0], tf[1], tf[2]);
        glUniform1f(loc_label_, single ? 1.f : (float)((i + 1) / 255.0));
        const GpuMesh& g = meshes_[handles[i]];
        glBindVertexArray(g.vao);
        glDrawElements(GL_TRIANGLES, g.num_indices, GL_UNSIGNED_INT, 0);
    }
    glBindVertexArray(0);
    // read back the region: colour + label (alpha), then z
    bgra_.create(roi.height, roi.width, CV_8UC4);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(roi.x, roi.y, roi.width, roi.height, GL_BGRA, GL_UNSIGNED_BYTE, bgra_.data);
    z_.create(roi.height, roi.width, CV_32F);
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(roi.x, roi.y, roi.width, roi.height, GL_RED, GL_FLOAT, z_.data);
    checkGL(fn);
}

// The object pixels are those with z > 0 (the z attachment is cleared to 0); depth, mask and
// labels are all derived from that one test so that they agree exactly.
void RendererImpl::readOutputs(Rect roi, bool single, OutputArray color, OutputArray depth,
                               OutputArray third)
{
    const Size size = size_;
    Mat c, d, l;
    if (color.needed())
    {
        color.create(size, CV_8UC3);
        c = color.getMat();
        c.setTo(Scalar::all(0));
        if (roi.area() > 0)
        {
            Mat c_roi = c(roi);
            const int from_to[] = { 0, 0, 1, 1, 2, 2 };
            mixChannels(&bgra_, 1, &c_roi, 1, from_to, 3);
        }
    }
    if (depth.needed())
    {
        depth.create(size, CV_16U);
        d = depth.getMat();
        d.setTo(Scalar::all(0));
    }
    if (third.needed())
    {
        third.create(size, CV_8U);
        l = third.getMat();
        l.setTo(Scalar::all(0));
    }
    for (int r = 0; r < roi.height && (!d.empty() || !l.empty()); ++r)
    {
        const float* zr = z_.ptr<float>(r);
        const uchar* a = bgra_.ptr<uchar>(r) + 3;
        ushort* dr = d.empty() ? 0 : d.ptr<ushort>(roi.y + r) + roi.x;
        uchar* lr = l.empty() ? 0 : l.ptr<uchar>(roi.y + r) + roi.x;
        for (int x = 0; x < roi.width; ++x)
        {
            const bool on = zr[x] > 0.f;
            if (dr)
                dr[x] = on ? (ushort)std::min(65535, std::max(1, cvRound(zr[x]))) : 0;
            if (lr)
                lr[x] = on ? (single ? 255 : a[4 * x]) : 0;
        }
    }
}

void RendererImpl::draw(const std::vector<int>& handles, const std::vector<Matx33d>& R,
                        const std::vector<Vec3d>& t, const Matx33d& K, bool single,
                        OutputArray color, OutputArray depth, OutputArray third)
{
    const char* fn = single ? "Renderer::render" : "Renderer::renderScene";
    AutoLock lock(mutex_);
    checkDraw(handles, R, t, K, fn);
    double znear = 0, zfar = 0;
    const Rect roi = drawRegion(handles, R, t, K, znear, zfar);
    if (roi.area() > 0)
        rasterize(handles, R, t, K, single, roi, znear, zfar, fn);
    readOutputs(roi, single, color, depth, third);
}

} // namespace

Ptr<Renderer> Renderer::create(Size size)
{
    return makePtr<RendererImpl>(size);
}

#else

Ptr<Renderer> Renderer::create(Size)
{
    CV_Error(Error::StsNotImplemented, "Renderer::create: forestmod was built without OSMesa");
}

#endif

} // namespace forestmod
} // namespace cv
