// OpenGL 3.3 core drawing of the body and the hair (viewer.h).
#include "viewer.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <tuple>
#include <unordered_map>

#include "ringlet/hair_bsdf.h"
#include "ringlet/render.h"

namespace ringlet::studio {
namespace {

// Hair: lines in, camera-facing quads out. The ribbon is the fibre's width; when that is below
// a pixel it is widened to one pixel and its alpha scaled by the coverage (so thin hair is not
// lost, and 50,000 strands do not turn into a solid block).
const char* kHairVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in float width;
layout(location = 2) in float flag;
out vec3 v_position;
out float v_width;
out float v_flag;
void main() { v_position = position; v_width = width; v_flag = flag; }
)";

const char* kHairGeometry = R"(#version 330 core
layout(lines) in;
layout(triangle_strip, max_vertices = 4) out;
in vec3 v_position[];
in float v_width[];
in float v_flag[];
uniform mat4 view_projection;
uniform vec3 eye;
uniform float pixels_per_unit;  // viewport height / (2 tan(fov / 2))
out vec3 g_tangent;
out vec3 g_position;
out float g_flag;
out float g_alpha;
void main() {
  vec3 t = v_position[1] - v_position[0];
  float len = length(t);
  if (len <= 0.0) return;
  t /= len;
  for (int k = 0; k < 2; ++k) {
    vec3 p = v_position[k];
    vec3 to_eye = normalize(eye - p);
    vec3 side = cross(t, to_eye);
    float s = length(side);
    side = s > 1e-6 ? side / s : vec3(1.0, 0.0, 0.0);
    // Pixels per metre at this depth, from the clip w.
    vec4 clip = view_projection * vec4(p, 1.0);
    float metres_per_pixel = clip.w / pixels_per_unit;
    float w = v_width[k];
    float half_width = 0.5 * max(w, metres_per_pixel);
    float alpha = clamp(w / metres_per_pixel, 0.25, 1.0);
    for (int j = 0; j < 2; ++j) {
      vec3 q = p + (j == 0 ? -half_width : half_width) * side;
      gl_Position = view_projection * vec4(q, 1.0);
      g_tangent = t;
      g_position = q;
      g_flag = v_flag[k];
      g_alpha = alpha;
      EmitVertex();
    }
  }
  EndPrimitive();
}
)";

// Hair thinner than a pixel (what the view shows unless zoomed in ~10x): plain GL lines, the
// geometry shader's outputs computed per vertex (the tangent from the strand's points, uploaded
// per point). The picture is the ribbons' (a one-pixel line, alpha the coverage) at a third of
// the cost under llvmpipe, whose geometry shaders are slow (2.5 us against 0.7 us a segment,
// measured; docs/benchmarks.md).
const char* kHairLineVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in float width;
layout(location = 2) in float flag;
layout(location = 3) in vec3 tangent;
uniform mat4 view_projection;
uniform float pixels_per_unit;
out vec3 g_tangent;
out vec3 g_position;
out float g_flag;
out float g_alpha;
void main() {
  vec4 clip = view_projection * vec4(position, 1.0);
  gl_Position = clip;
  g_tangent = tangent;
  g_position = position;
  g_flag = flag;
  g_alpha = clamp(width / (clip.w / pixels_per_unit), 0.25, 1.0);
}
)";

// Kajiya-Kay diffuse + two highlights of Marschner's model: R (white, shifted toward the tip by
// the cuticle tilt) and TRT (coloured, shifted the other way, broader).
const char* kHairFragment = R"(#version 330 core
in vec3 g_tangent;
in vec3 g_position;
in float g_flag;
in float g_alpha;
uniform vec3 eye;
uniform vec3 light;
uniform vec3 colour;
uniform vec3 head_centre;
uniform float head_radius;
uniform int highlight_masters;
out vec4 out_colour;
float KajiyaKaySpecular(vec3 t, vec3 h, float e) {
  float th = dot(t, h);
  return pow(sqrt(max(0.0, 1.0 - th * th)), e);
}
void main() {
  vec3 t = normalize(g_tangent);
  vec3 v = normalize(eye - g_position);
  vec3 l = normalize(light);
  vec3 h = normalize(l + v);
  vec3 n = normalize(v - dot(v, t) * t);  // the ribbon's normal, toward the eye
  float tl = dot(t, l);
  float diffuse = sqrt(max(0.0, 1.0 - tl * tl));
  float r = KajiyaKaySpecular(normalize(t - 0.08 * n), h, 120.0);
  float trt = KajiyaKaySpecular(normalize(t + 0.12 * n), h, 25.0);
  // Ambient darkening: hair near the scalp lies under other hair.
  float depth = clamp((length(g_position - head_centre) - head_radius) / (0.6 * head_radius), 0.0, 1.0);
  float ambient_occlusion = 0.45 + 0.55 * depth;
  vec3 base = colour;
  if (g_flag > 3.5) base = vec3(1.0, 0.1, 0.9);         // unstable master: magenta
  else if (g_flag > 2.5) base = vec3(1.0, 0.15, 0.05);  // unconverged master: red
  else if (g_flag > 1.5) base = vec3(0.1, 0.9, 1.0);    // brushed: cyan
  else if (g_flag > 0.5 && highlight_masters == 1) base = vec3(1.0, 0.85, 0.2);  // master
  vec3 c = base * (0.15 + 0.85 * diffuse) * ambient_occlusion + 0.35 * r * vec3(1.0) +
           0.5 * trt * base * 2.0 * ambient_occlusion;
  out_colour = vec4(c, g_alpha);
}
)";

const char* kBodyVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 view_projection;
out vec3 f_normal;
void main() { f_normal = normal; gl_Position = view_projection * vec4(position, 1.0); }
)";

const char* kBodyFragment = R"(#version 330 core
in vec3 f_normal;
uniform vec3 light;
out vec4 out_colour;
void main() {
  vec3 n = normalize(f_normal);
  float d = max(0.0, dot(n, normalize(light)));
  float sky = 0.5 + 0.5 * n.z;
  vec3 albedo = vec3(0.55, 0.42, 0.36);
  out_colour = vec4(albedo * (0.9 * d + 0.25 * sky + 0.08), 1.0);
}
)";

// The cut gizmo: flat colour with alpha.
const char* kGizmoVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 view_projection;
void main() { gl_Position = view_projection * vec4(position, 1.0); }
)";
const char* kGizmoFragment = R"(#version 330 core
uniform vec4 colour;
out vec4 out_colour;
void main() { out_colour = colour; }
)";

// The refining picture on screen: a triangle over the view, the off-screen colour and depth.
const char* kCompositeVertex = R"(#version 330 core
void main() {
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  gl_Position = vec4(p, 0.0, 1.0);
}
)";
const char* kCompositeFragment = R"(#version 330 core
uniform sampler2D colour;
uniform sampler2D depth;
uniform vec2 origin;
uniform vec2 size;
out vec4 out_colour;
void main() {
  vec2 uv = (gl_FragCoord.xy - origin) / size;
  out_colour = texture(colour, uv);
  gl_FragDepth = texture(depth, uv).r;
}
)";

unsigned Compile(GLenum type, const char* source, std::string* error) {
  const unsigned shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetShaderInfoLog(shader, sizeof(log), nullptr, log);
    *error = std::string("shader: ") + log;
    return 0;
  }
  return shader;
}

unsigned Link(std::initializer_list<std::pair<GLenum, const char*>> stages, std::string* error) {
  const unsigned program = glCreateProgram();
  for (const auto& [type, source] : stages) {
    const unsigned s = Compile(type, source, error);
    if (!s) return 0;
    glAttachShader(program, s);
    glDeleteShader(s);
  }
  glLinkProgram(program);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetProgramInfoLog(program, sizeof(log), nullptr, log);
    *error = std::string("program: ") + log;
    return 0;
  }
  return program;
}

void SetMatrix(unsigned program, const char* name, const Eigen::Matrix4f& m) {
  glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_FALSE, m.data());
}
void SetVec3(unsigned program, const char* name, const Eigen::Vector3f& v) {
  glUniform3f(glGetUniformLocation(program, name), v.x(), v.y(), v.z());
}

}  // namespace

Eigen::Vector3f MelaninColour(double eumelanin, double pheomelanin) {
  const Rgb sigma = AbsorptionFromMelanin(eumelanin, pheomelanin);
  Eigen::Vector3f c;
  for (int k = 0; k < 3; ++k) c[k] = static_cast<float>(std::exp(-3.0 * sigma[k]));
  return c.cwiseMax(0.01f);
}

Eigen::Vector3f PathTracedHairColour(const RenderSettings& settings, double eccentricity) {
  // The swatch: 6 layers of 40 horizontal fibres (along x) of 80 um, 0.1 mm apart (opaque),
  // 4 cm long, behind the plane y = 0; the camera looks at it from the front (+y, the face's
  // side) from 10 cm, so that the default key light (above, in front) falls across the fibres.
  HairCurves swatch;
  const int columns = 40, layers = 6;
  for (int l = 0; l < layers; ++l) {
    for (int c = 0; c < columns; ++c) {
      const float z = (c - 0.5f * columns + 0.5f * (l % 2)) * 1e-4f, y = -l * 1e-4f;
      swatch.point_counts.push_back(4);
      for (int k = 0; k < 4; ++k) {
        swatch.points.emplace_back(-0.02f + k * 0.04f / 3.0f, y, z);
        swatch.widths.push_back(8e-5f);
      }
    }
  }
  RenderSettings s = settings;
  s.options.width = s.options.height = 12;
  s.options.samples_per_pixel = 8;
  s.options.denoise = false;
  s.camera.kind = CameraSettings::Kind::kExplicit;
  s.camera.position = Vec3(0.0, 0.1, 0.0);
  s.camera.look_at = Vec3::Zero();
  s.camera.up = Vec3::UnitZ();
  s.camera.vertical_fov = 2.0 * std::atan(0.0015 / 0.1);  // 3 mm of the swatch's middle
  RenderScene scene;
  Image image;
  RenderStats stats;
  std::string error;
  if (!MakeRenderScene(s, &swatch, nullptr, eccentricity, 1, &scene, &error) ||
      !Render(scene, s.options, &image, &stats, &error) || image.pixels.empty()) {
    return MelaninColour(settings.eumelanin, settings.pheomelanin);
  }
  Eigen::Vector3f mean = Eigen::Vector3f::Zero();
  for (const Eigen::Vector3f& p : image.pixels) mean += p;
  mean *= static_cast<float>(settings.exposure) / static_cast<float>(image.pixels.size());
  return mean.cwiseMax(0.0f).cwiseMin(1.0f);
}

// ---------------------------------------------------------------------------------------------
// Camera

Eigen::Vector3f OrbitCamera::Position() const {
  const Eigen::Vector3f back(std::sin(yaw) * std::cos(pitch), -std::cos(yaw) * std::cos(pitch),
                             std::sin(pitch));
  return target + distance * back;
}

Eigen::Matrix4f OrbitCamera::View() const {
  const Eigen::Vector3f eye = Position();
  const Eigen::Vector3f f = (target - eye).normalized();
  const Eigen::Vector3f s = f.cross(Eigen::Vector3f::UnitZ()).normalized();
  const Eigen::Vector3f u = s.cross(f);
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m.block<1, 3>(0, 0) = s.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -s.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = f.dot(eye);
  return m;
}

Eigen::Matrix4f OrbitCamera::Projection(float aspect) const {
  const float near = std::max(1e-3f, distance * 0.02f), far = distance * 20.0f;
  const float f = 1.0f / std::tan(0.5f * fov);
  Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
  m(0, 0) = f / aspect;
  m(1, 1) = f;
  m(2, 2) = (far + near) / (near - far);
  m(2, 3) = 2.0f * far * near / (near - far);
  m(3, 2) = -1.0f;
  return m;
}

void OrbitCamera::Orbit(float dyaw, float dpitch) {
  yaw += dyaw;
  pitch = std::clamp(pitch + dpitch, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::LookFrom(const Eigen::Vector3f& direction) {
  const float n = direction.norm();
  if (!(n > 0.0f)) return;
  const Eigen::Vector3f b = direction / n;
  // Position() - target = distance (sin yaw cos pitch, -cos yaw cos pitch, sin pitch).
  pitch = std::clamp(std::asin(std::clamp(b.z(), -1.0f, 1.0f)), -kMaxPitch, kMaxPitch);
  if (b.x() != 0.0f || b.y() != 0.0f) yaw = std::atan2(b.x(), -b.y());
}

void OrbitCamera::SetView(ViewSide side) {
  const float pi = 3.1415927f;
  switch (side) {
    case ViewSide::kFront:
      yaw = pi, pitch = 0.0f;
      break;
    case ViewSide::kBack:
      yaw = 0.0f, pitch = 0.0f;
      break;
    case ViewSide::kRight:  // the head's right (+x)
      yaw = 0.5f * pi, pitch = 0.0f;
      break;
    case ViewSide::kLeft:
      yaw = -0.5f * pi, pitch = 0.0f;
      break;
    case ViewSide::kTop:
      yaw = pi, pitch = kMaxPitch;
      break;
    case ViewSide::kBottom:
      yaw = pi, pitch = -kMaxPitch;
      break;
  }
}

void OrbitCamera::Pan(float dx, float dy) {
  const Eigen::Matrix4f v = View();
  const Eigen::Vector3f s = v.block<1, 3>(0, 0).transpose();
  const Eigen::Vector3f u = v.block<1, 3>(1, 0).transpose();
  target += distance * (dx * s + dy * u);
}

void OrbitCamera::Zoom(float factor) { distance = std::clamp(distance * factor, 0.02f, 50.0f); }

void OrbitCamera::Frame(const Eigen::AlignedBox3f& box) {
  if (box.isEmpty()) return;
  target = box.center();
  const float radius = 0.5f * box.diagonal().norm();
  distance = radius / std::sin(0.5f * fov) * 1.02f;
}

// ---------------------------------------------------------------------------------------------
// Viewer

Viewer::Viewer() = default;

Viewer::~Viewer() {
  for (StrandBuffers* g : {&hair_gl_, &preview_gl_}) {
    if (g->vao) glDeleteVertexArrays(1, &g->vao);
    for (unsigned b : {g->vbo, g->tangent_vbo, g->flag_vbo, g->ebo}) {
      if (b) glDeleteBuffers(1, &b);
    }
  }
  for (unsigned a : {body_vao_, coarse_body_vao_}) {
    if (a) glDeleteVertexArrays(1, &a);
  }
  for (unsigned b : {body_vbo_, coarse_body_vbo_}) {
    if (b) glDeleteBuffers(1, &b);
  }
  if (hair_program_) glDeleteProgram(hair_program_);
  if (line_program_) glDeleteProgram(line_program_);
  if (gizmo_program_) glDeleteProgram(gizmo_program_);
  if (gizmo_vao_) glDeleteVertexArrays(1, &gizmo_vao_);
  if (gizmo_vbo_) glDeleteBuffers(1, &gizmo_vbo_);
  if (body_program_) glDeleteProgram(body_program_);
  if (composite_program_) glDeleteProgram(composite_program_);
  if (refine_fbo_) glDeleteFramebuffers(1, &refine_fbo_);
  if (refine_colour_) glDeleteTextures(1, &refine_colour_);
  if (refine_depth_) glDeleteTextures(1, &refine_depth_);
}

bool Viewer::Init(std::string* error) {
  hair_program_ = Link({{GL_VERTEX_SHADER, kHairVertex},
                        {GL_GEOMETRY_SHADER, kHairGeometry},
                        {GL_FRAGMENT_SHADER, kHairFragment}},
                       error);
  line_program_ =
      Link({{GL_VERTEX_SHADER, kHairLineVertex}, {GL_FRAGMENT_SHADER, kHairFragment}}, error);
  body_program_ =
      Link({{GL_VERTEX_SHADER, kBodyVertex}, {GL_FRAGMENT_SHADER, kBodyFragment}}, error);
  gizmo_program_ =
      Link({{GL_VERTEX_SHADER, kGizmoVertex}, {GL_FRAGMENT_SHADER, kGizmoFragment}}, error);
  composite_program_ =
      Link({{GL_VERTEX_SHADER, kCompositeVertex}, {GL_FRAGMENT_SHADER, kCompositeFragment}}, error);
  if (!hair_program_ || !line_program_ || !body_program_ || !gizmo_program_ ||
      !composite_program_) {
    return false;
  }
  glGenVertexArrays(1, &gizmo_vao_);
  glGenBuffers(1, &gizmo_vbo_);
  for (StrandBuffers* g : {&hair_gl_, &preview_gl_}) {
    glGenVertexArrays(1, &g->vao);
    glGenBuffers(1, &g->vbo);
    glGenBuffers(1, &g->tangent_vbo);
    glGenBuffers(1, &g->flag_vbo);
    glGenBuffers(1, &g->ebo);
  }
  glGenVertexArrays(1, &body_vao_);
  glGenBuffers(1, &body_vbo_);
  glGenVertexArrays(1, &coarse_body_vao_);
  glGenBuffers(1, &coarse_body_vbo_);
  return true;
}

namespace {

// The unit tangent of a strand at each of its points (toward the tip: the next segment's
// direction, the last point its segment's), 3 normalized signed bytes and a pad per point.
void StrandTangents(const HairCurves& c, size_t first_point, size_t count, std::int8_t* out) {
  for (size_t p = 0; p < count; ++p) {
    const size_t q = first_point + p;
    const bool last = p + 1 == count;
    Eigen::Vector3f t = last ? Eigen::Vector3f(c.points[q] - c.points[q - 1])
                             : Eigen::Vector3f(c.points[q + 1] - c.points[q]);
    const float n = t.norm();
    t = n > 0.0f ? Eigen::Vector3f(t / n) : Eigen::Vector3f::UnitZ();
    for (int k = 0; k < 3; ++k) out[4 * p + k] = static_cast<std::int8_t>(std::lround(127.0f * t[k]));
    out[4 * p + 3] = 0;
  }
}

// The body's triangles (6 floats per corner: position, normal) for the frames while the camera
// moves: about a sixth of them (CoarseBody, below UploadBody).
std::vector<float> CoarseBody(const std::vector<float>& triangles);

void TangentsOfAll(const HairCurves& c, std::vector<std::int8_t>* out) {
  out->assign(4 * c.points.size(), 0);
  size_t first = 0;
  for (std::uint32_t count : c.point_counts) {
    if (count >= 2) StrandTangents(c, first, count, out->data() + 4 * first);
    first += count;
  }
}

}  // namespace

void Viewer::UploadStrands(StrandBuffers* g, const HairCurves& c,
                           const std::vector<std::uint32_t>& indices) {
  std::vector<float> data(4 * c.points.size());
  g->max_width = 0.0f;
  for (size_t i = 0; i < c.points.size(); ++i) {
    data[4 * i + 0] = c.points[i].x();
    data[4 * i + 1] = c.points[i].y();
    data[4 * i + 2] = c.points[i].z();
    data[4 * i + 3] = c.widths[i];
    g->max_width = std::max(g->max_width, c.widths[i]);
  }
  std::vector<std::int8_t> tangents;
  TangentsOfAll(c, &tangents);
  glBindVertexArray(g->vao);
  glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
  glBufferData(GL_ARRAY_BUFFER, data.size() * sizeof(float), data.data(), GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, 4 * sizeof(float),
                        reinterpret_cast<void*>(3 * sizeof(float)));
  glBindBuffer(GL_ARRAY_BUFFER, g->tangent_vbo);
  glBufferData(GL_ARRAY_BUFFER, tangents.size(), tangents.data(), GL_STATIC_DRAW);
  glEnableVertexAttribArray(3);
  glVertexAttribPointer(3, 3, GL_BYTE, GL_TRUE, 4, nullptr);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ebo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, indices.size() * 4, indices.data(), GL_STATIC_DRAW);
  glBindVertexArray(0);
  g->indices = static_cast<long>(indices.size());
  last_upload_bytes_ = static_cast<long>(data.size() * 4 + tangents.size() + indices.size() * 4);
}

void Viewer::SetPreview(const std::shared_ptr<const HairState>& preview) {
  if (preview == preview_) return;
  preview_ = preview;
  ++hair_version_;
  if (!preview || !preview->strands) return;
  const HairCurves& c = *preview->strands;
  // Every master in order, all flagged as masters.
  std::vector<std::uint32_t> indices;
  indices.reserve(2 * c.points.size());
  std::uint32_t first = 0;
  for (std::uint32_t count : c.point_counts) {
    for (std::uint32_t p = first; p + 1 < first + count; ++p) {
      indices.push_back(p);
      indices.push_back(p + 1);
    }
    first += count;
  }
  const long hair_upload = last_upload_bytes_;  // LastUploadBytes is the hair's
  UploadStrands(&preview_gl_, c, indices);
  last_upload_bytes_ = hair_upload;
  preview_gl_.master_indices = preview_gl_.indices;
  const std::vector<float> flags(c.points.size(), 1.0f);
  glBindVertexArray(preview_gl_.vao);
  glBindBuffer(GL_ARRAY_BUFFER, preview_gl_.flag_vbo);
  glBufferData(GL_ARRAY_BUFFER, flags.size() * sizeof(float), flags.data(), GL_DYNAMIC_DRAW);
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, sizeof(float), nullptr);
  glBindVertexArray(0);
  const Body* body = preview->styled.style.body.get();
  if (body && body != body_) {
    body_ = body;
    UploadBody(*body_);
  }
  // Another file's masters: the box starts again (the hair on the GPU is the old file's).
  if (!hair_ || hair_->styled.style.body.get() != body) bounds_.setEmpty();
  ExtendBounds(c);
}

void Viewer::ExtendBounds(const HairCurves& c) {
  for (const Vec3f& x : c.points) bounds_.extend(x);
  if (body_) {
    const Box3& b = body_->Bounds();
    if (!b.isEmpty()) {
      bounds_.extend(b.min().cast<float>());
      bounds_.extend(b.max().cast<float>());
    }
  }
}

void Viewer::SetHair(const std::shared_ptr<const HairState>& hair) {
  // Only some wisps regrown from the strands on the GPU (same layout): upload those slices.
  if (hair && hair->strands && hair_ && hair_->strands && hair->regrown_from != 0 &&
      hair->regrown_from == hair_->strands_id &&
      hair->strands->points.size() == hair_->strands->points.size()) {
    const HairCurves& c = *hair->strands;
    const int masters = static_cast<int>(hair->styled.masters.models.size());
    const size_t per_master = masters > 0 ? c.points.size() / masters : 0;
    std::vector<float> data(4 * per_master);
    std::vector<std::int8_t> tangents(4 * per_master);
    const int per_wisp = masters > 0 ? std::max(1, c.NumStrands() / masters) : 1;
    std::vector<size_t> first_point(c.NumStrands() + 1, 0);
    for (int k = 0; k < c.NumStrands(); ++k) first_point[k + 1] = first_point[k] + c.point_counts[k];
    for (int i : hair->regrown) {
      const size_t first = static_cast<size_t>(i) * per_master;
      for (size_t p = 0; p < per_master; ++p) {
        const Vec3f& x = c.points[first + p];
        data[4 * p + 0] = x.x();
        data[4 * p + 1] = x.y();
        data[4 * p + 2] = x.z();
        data[4 * p + 3] = c.widths[first + p];
        hair_gl_.max_width = std::max(hair_gl_.max_width, c.widths[first + p]);
        bounds_.extend(x);
      }
      // The tangents of the wisp's strands (strands_per_wisp whole strands of the slice).
      for (int k = i * per_wisp; k < (i + 1) * per_wisp && k < c.NumStrands(); ++k) {
        if (c.point_counts[k] >= 2) {
          StrandTangents(c, first_point[k], c.point_counts[k],
                         tangents.data() + 4 * (first_point[k] - first));
        }
      }
      glBindBuffer(GL_ARRAY_BUFFER, hair_gl_.vbo);
      glBufferSubData(GL_ARRAY_BUFFER, static_cast<GLintptr>(4 * first * sizeof(float)),
                      static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data());
      glBindBuffer(GL_ARRAY_BUFFER, hair_gl_.tangent_vbo);
      glBufferSubData(GL_ARRAY_BUFFER, static_cast<GLintptr>(4 * first),
                      static_cast<GLsizeiptr>(tangents.size()), tangents.data());
    }
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    hair_ = hair;
    last_upload_bytes_ = static_cast<long>(hair->regrown.size() * per_master * 20);
    UploadFlags();
    return;
  }
  hair_ = hair;
  ++hair_version_;
  bounds_.setEmpty();
  if (!hair || !hair->strands) return;
  const HairCurves& c = *hair->strands;
  // The segments in drawing order: the masters (the first strand of each wisp) first, then the
  // first child of every wisp, the second, ...; wisps in the order of the radical inverse of
  // their index (van der Corput, base 2), so that any prefix of the order (the preview density,
  // Draw's max_segments) is the masters and an even subset of the children.
  const int masters = static_cast<int>(hair->styled.masters.models.size());
  const int per_wisp = masters > 0 ? std::max(1, c.NumStrands() / masters) : 1;
  std::vector<std::uint32_t> first_point(c.NumStrands() + 1, 0);
  for (int k = 0; k < c.NumStrands(); ++k) first_point[k + 1] = first_point[k] + c.point_counts[k];
  std::vector<int> wisp_order(masters);
  for (int i = 0; i < masters; ++i) wisp_order[i] = i;
  const auto radical_inverse = [](std::uint32_t i) {
    std::uint32_t r = 0;
    for (int b = 0; b < 32; ++b, i >>= 1) r = (r << 1) | (i & 1u);
    return r;
  };
  std::stable_sort(wisp_order.begin(), wisp_order.end(), [&](int a, int b) {
    return radical_inverse(static_cast<std::uint32_t>(a)) <
           radical_inverse(static_cast<std::uint32_t>(b));
  });
  std::vector<std::uint32_t> all;
  all.reserve(2 * c.points.size());
  const auto add_strand = [&](int k) {
    for (std::uint32_t p = first_point[k]; p + 1 < first_point[k + 1]; ++p) {
      all.push_back(p);
      all.push_back(p + 1);
    }
  };
  strand_of_master_.assign(masters, 0);
  for (int j = 0; j < per_wisp; ++j) {
    for (const int w : wisp_order) {
      const int k = w * per_wisp + j;
      if (k < c.NumStrands()) add_strand(k);
      if (j == 0) strand_of_master_[w] = static_cast<std::uint32_t>(k);
    }
    if (j == 0) hair_gl_.master_indices = static_cast<long>(all.size());
  }
  // Strands beyond masters x per_wisp (none in the hairstyle's layout) come last.
  for (int k = masters * per_wisp; k < c.NumStrands(); ++k) add_strand(k);
  if (masters == 0) hair_gl_.master_indices = 0;
  UploadStrands(&hair_gl_, c, all);
  UploadFlags();
  if (hair->styled.style.body.get() != body_) {
    body_ = hair->styled.style.body.get();
    if (body_) UploadBody(*body_);
  }
  ExtendBounds(c);
}

void Viewer::SetBrush(const std::vector<int>& masters) {
  brush_ = masters;
  UploadFlags();
}

void Viewer::UploadFlags() {
  ++hair_version_;
  if (!hair_ || !hair_->strands) return;
  const HairCurves& c = *hair_->strands;
  const int masters = static_cast<int>(hair_->styled.masters.models.size());
  const int per_wisp = masters > 0 ? std::max(1, c.NumStrands() / masters) : 1;
  std::vector<float> master_flag(masters, 0.0f);
  for (int i = 0; i < masters; ++i) {
    const MasterStatus s =
        i < static_cast<int>(hair_->status.size()) ? hair_->status[i] : MasterStatus::kConverged;
    master_flag[i] = s == MasterStatus::kUnstable      ? 4.0f
                     : s == MasterStatus::kUnconverged ? 3.0f
                                                       : 0.0f;
  }
  for (int i : brush_) {
    if (i >= 0 && i < masters && master_flag[i] == 0.0f) master_flag[i] = 2.0f;
  }
  std::vector<float> flags(c.points.size());
  size_t p = 0;
  for (int k = 0; k < c.NumStrands(); ++k) {
    const int wisp = std::min(masters - 1, k / per_wisp);
    float f = masters > 0 ? master_flag[wisp] : 0.0f;
    if (f == 0.0f && k % per_wisp == 0) f = 1.0f;
    for (std::uint32_t j = 0; j < c.point_counts[k]; ++j) flags[p++] = f;
  }
  glBindVertexArray(hair_gl_.vao);
  glBindBuffer(GL_ARRAY_BUFFER, hair_gl_.flag_vbo);
  glBufferData(GL_ARRAY_BUFFER, flags.size() * sizeof(float), flags.data(), GL_DYNAMIC_DRAW);
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, sizeof(float), nullptr);
  glBindVertexArray(0);
}

void Viewer::UploadBody(const Body& body) {
  // Triangles with normals: each sphere tessellated (48 x 24), each mesh with face normals.
  std::vector<float> data;
  const auto vertex = [&data](const Vec3& p, const Vec3& n) {
    for (int k = 0; k < 3; ++k) data.push_back(static_cast<float>(p[k]));
    for (int k = 0; k < 3; ++k) data.push_back(static_cast<float>(n[k]));
  };
  for (const Sphere& s : body.spheres()) {
    const int nu = 48, nv = 24;
    const auto at = [&](int i, int j) {
      const double u = 2.0 * M_PI * i / nu, v = M_PI * j / nv;
      return Vec3(std::sin(v) * std::cos(u), std::sin(v) * std::sin(u), std::cos(v));
    };
    for (int i = 0; i < nu; ++i) {
      for (int j = 0; j < nv; ++j) {
        const Vec3 a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
        for (const Vec3& n : {a, b, c, a, c, d}) vertex(s.center + s.radius * n, n);
      }
    }
  }
  for (const TriangleMesh& m : body.meshes()) {
    for (const auto& t : m.triangles()) {
      const Vec3& a = m.vertices()[t[0]];
      const Vec3& b = m.vertices()[t[1]];
      const Vec3& c = m.vertices()[t[2]];
      const Vec3 n = (b - a).cross(c - a).normalized();
      vertex(a, n);
      vertex(b, n);
      vertex(c, n);
    }
  }
  body_vertices_ = static_cast<long>(data.size() / 6);
  const std::vector<float> coarse = CoarseBody(data);
  coarse_body_vertices_ = static_cast<long>(coarse.size() / 6);
  for (const auto& [vao, vbo, triangles] :
       {std::tuple<unsigned, unsigned, const std::vector<float>*>{body_vao_, body_vbo_, &data},
        std::tuple<unsigned, unsigned, const std::vector<float>*>{coarse_body_vao_,
                                                                   coarse_body_vbo_, &coarse}}) {
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, triangles->size() * sizeof(float), triangles->data(),
                 GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                          reinterpret_cast<void*>(3 * sizeof(float)));
  }
  glBindVertexArray(0);
}

namespace {

std::vector<float> CoarseBody(const std::vector<float>& triangles) {
  // Vertex clustering (Rossignac and Borrel 1993): the vertices on a grid of cells 2.5 mean
  // edge lengths wide, each cell's vertices merged at their mean, the triangles whose corners
  // fall in three different cells kept (with their new face normal, on the side of the old).
  const size_t n = triangles.size() / 18;
  const auto at = [&](size_t t, int k) {
    return Eigen::Vector3f(triangles[18 * t + 6 * k], triangles[18 * t + 6 * k + 1],
                           triangles[18 * t + 6 * k + 2]);
  };
  double edges = 0.0;
  for (size_t t = 0; t < n; ++t) edges += (at(t, 1) - at(t, 0)).norm();
  if (n < 2000 || !(edges > 0.0)) return triangles;  // small enough as it is
  const float cell = static_cast<float>(2.5 * edges / static_cast<double>(n));
  std::unordered_map<std::uint64_t, int> cluster_of;
  std::vector<Eigen::Vector3f> sums;
  std::vector<int> counts, corner(3 * n);
  for (size_t t = 0; t < n; ++t) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3f p = at(t, k);
      std::uint64_t key = 0;
      for (int a = 0; a < 3; ++a) {
        key = key * 2097152u +
              static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(p[a] / cell)) +
                                         1048576) % 2097152u;
      }
      const auto [it, inserted] = cluster_of.emplace(key, static_cast<int>(sums.size()));
      if (inserted) {
        sums.push_back(Eigen::Vector3f::Zero());
        counts.push_back(0);
      }
      sums[it->second] += p;
      ++counts[it->second];
      corner[3 * t + k] = it->second;
    }
  }
  std::vector<float> out;
  for (size_t t = 0; t < n; ++t) {
    const int a = corner[3 * t], b = corner[3 * t + 1], c = corner[3 * t + 2];
    if (a == b || b == c || a == c) continue;
    const Eigen::Vector3f pa = sums[a] / counts[a], pb = sums[b] / counts[b],
                          pc = sums[c] / counts[c];
    Eigen::Vector3f normal = (pb - pa).cross(pc - pa);
    if (!(normal.norm() > 0.0f)) continue;
    normal.normalize();
    const Eigen::Vector3f old(triangles[18 * t + 3], triangles[18 * t + 4], triangles[18 * t + 5]);
    if (normal.dot(old) < 0.0f) normal = -normal;
    for (const Eigen::Vector3f* p : {&pa, &pb, &pc}) {
      out.insert(out.end(), {p->x(), p->y(), p->z(), normal.x(), normal.y(), normal.z()});
    }
  }
  return out;
}

}  // namespace

Viewer::Scene Viewer::MakeScene(const OrbitCamera& camera, const HairLook& look, int width,
                                int height) const {
  Scene scene;
  scene.vp = camera.Projection(static_cast<float>(width) / std::max(1, height)) * camera.View();
  scene.eye = camera.Position();
  // The key light: the hairstyle's (fixed in the scene, as the path tracer's), or a headlight
  // from the camera, raised a little (a quarter of the view's up) so that the hair keeps some
  // modelling.
  scene.light = look.key_light;
  if (look.headlight) {
    const Eigen::Matrix4f view = camera.View();
    // The view's third row is -forward: from the target toward the eye.
    const Eigen::Vector3f back = view.block<1, 3>(2, 0).transpose();
    const Eigen::Vector3f up = view.block<1, 3>(1, 0).transpose();
    scene.light = (back + 0.25f * up).normalized();
  }
  scene.pixels_per_unit = 0.5f * height / std::tan(0.5f * camera.fov);
  // What is drawn: the masters being solved (SetPreview), else the hair.
  const bool preview = preview_ && preview_->strands;
  scene.strands = preview ? &preview_gl_ : &hair_gl_;
  scene.segments = (look.masters_only ? scene.strands->master_indices : scene.strands->indices) / 2;
  if (!preview && (!hair_ || !hair_->strands)) scene.segments = 0;
  scene.scalp = preview ? &preview_->styled.style.scalp
                        : hair_ ? &hair_->styled.style.scalp : nullptr;
  // Lines instead of ribbons when every fibre is thinner than a pixel at the nearest depth of
  // the hair and body box (clip w = the view depth; the depth is linear: its least value over
  // the box is at a corner).
  float nearest = std::numeric_limits<float>::infinity();
  const Eigen::Matrix4f view = camera.View();
  for (int k = 0; k < 8 && !bounds_.isEmpty(); ++k) {
    const Eigen::Vector3f corner = bounds_.corner(static_cast<Eigen::AlignedBox3f::CornerType>(k));
    nearest = std::min(nearest, -(view * corner.homogeneous()).z());
  }
  scene.lines = nearest > 0.0f && scene.strands->max_width <= nearest / scene.pixels_per_unit;
  return scene;
}

void Viewer::DrawBody(const Scene& scene, bool coarse) {
  if (body_vertices_ <= 0) return;
  glUseProgram(body_program_);
  SetMatrix(body_program_, "view_projection", scene.vp);
  SetVec3(body_program_, "light", scene.light);
  glBindVertexArray(coarse ? coarse_body_vao_ : body_vao_);
  glDrawArrays(GL_TRIANGLES, 0,
               static_cast<GLsizei>(coarse ? coarse_body_vertices_ : body_vertices_));
}

void Viewer::DrawHair(const Scene& scene, const HairLook& look, long first, long count) {
  if (count <= 0 || !scene.scalp) return;
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  const unsigned program = scene.lines ? line_program_ : hair_program_;
  glUseProgram(program);
  SetMatrix(program, "view_projection", scene.vp);
  SetVec3(program, "eye", scene.eye);
  SetVec3(program, "light", scene.light);
  SetVec3(program, "colour", look.colour);
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  float radius = 0.1f;
  if (const auto* s = std::get_if<SphereScalp>(scene.scalp)) {
    centre = s->head.centre.cast<float>();
    radius = static_cast<float>(s->radius);
  }
  SetVec3(program, "head_centre", centre);
  glUniform1f(glGetUniformLocation(program, "head_radius"), radius);
  glUniform1i(glGetUniformLocation(program, "highlight_masters"),
              look.highlight_masters || look.masters_only ? 1 : 0);
  glUniform1f(glGetUniformLocation(program, "pixels_per_unit"), scene.pixels_per_unit);
  glBindVertexArray(scene.strands->vao);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, scene.strands->ebo);
  glDrawElements(GL_LINES, static_cast<GLsizei>(2 * count), GL_UNSIGNED_INT,
                 reinterpret_cast<void*>(static_cast<std::uintptr_t>(2 * first * 4)));
  glDisable(GL_BLEND);
}

void Viewer::Draw(const OrbitCamera& camera, const HairLook& look, int x0, int full_width,
                  int height, long max_segments) {
  glViewport(0, 0, full_width, height);
  glClearColor(0.16f, 0.17f, 0.2f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  const int width = std::max(1, full_width - x0);
  glViewport(x0, 0, width, height);
  glEnable(GL_DEPTH_TEST);
  const Scene scene = MakeScene(camera, look, width, height);
  DrawBody(scene, /*coarse=*/max_segments >= 0);  // a preview: the body coarse too
  const long n = max_segments >= 0 ? std::min(scene.segments, max_segments) : scene.segments;
  DrawHair(scene, look, 0, n);
  drew_lines_ = scene.lines;
  drawn_segments_ = last_draw_segments_ = n;
  refined_ = -1;  // the refining picture is not on screen any more
  if (gizmo_) DrawGizmo(scene.vp);
  glBindVertexArray(0);
  glUseProgram(0);
}

bool Viewer::DrawRefining(const OrbitCamera& camera, const HairLook& look, int x0, int full_width,
                          int height, long chunk) {
  const int width = std::max(1, full_width - x0);
  const Scene scene = MakeScene(camera, look, width, height);
  // The picture's inputs: when any differs from the picture being refined, it starts again.
  const std::vector<float> key = {camera.yaw,
                                  camera.pitch,
                                  camera.distance,
                                  camera.fov,
                                  camera.target.x(),
                                  camera.target.y(),
                                  camera.target.z(),
                                  look.colour.x(),
                                  look.colour.y(),
                                  look.colour.z(),
                                  look.masters_only ? 1.0f : 0.0f,
                                  look.highlight_masters ? 1.0f : 0.0f,
                                  look.headlight ? 1.0f : 0.0f,
                                  look.key_light.x(),
                                  look.key_light.y(),
                                  look.key_light.z(),
                                  static_cast<float>(width),
                                  static_cast<float>(height),
                                  static_cast<float>(hair_version_),
                                  static_cast<float>(body_vertices_)};
  if (width != refine_width_ || height != refine_height_) {
    // The off-screen picture: colour and depth textures of the view's size.
    if (!refine_fbo_) {
      glGenFramebuffers(1, &refine_fbo_);
      glGenTextures(1, &refine_colour_);
      glGenTextures(1, &refine_depth_);
    }
    glBindTexture(GL_TEXTURE_2D, refine_colour_);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, refine_depth_);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, width, height, 0, GL_DEPTH_COMPONENT,
                 GL_UNSIGNED_INT, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, refine_fbo_);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, refine_colour_, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, refine_depth_, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    refine_width_ = width;
    refine_height_ = height;
    refine_key_.clear();
  }
  glBindFramebuffer(GL_FRAMEBUFFER, refine_fbo_);
  glViewport(0, 0, width, height);
  glEnable(GL_DEPTH_TEST);
  if (key != refine_key_ || refined_ < 0) {
    refine_key_ = key;
    glClearColor(0.16f, 0.17f, 0.2f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    DrawBody(scene, /*coarse=*/false);
    refined_ = 0;
  }
  // The next chunk of the drawing order (the same segments, blended in the same order, as one
  // draw call of them all).
  const long count = std::min(std::max(1L, chunk), scene.segments - refined_);
  DrawHair(scene, look, refined_, count);
  drew_lines_ = scene.lines;
  refined_ += std::max(0L, count);
  last_draw_segments_ = std::max(0L, count);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  // On screen: the picture so far (colour and depth, so that the gizmo is hidden behind the
  // head as in Draw), then the gizmo.
  glViewport(0, 0, full_width, height);
  glClearColor(0.16f, 0.17f, 0.2f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glViewport(x0, 0, width, height);
  glUseProgram(composite_program_);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, refine_depth_);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, refine_colour_);
  glUniform1i(glGetUniformLocation(composite_program_, "colour"), 0);
  glUniform1i(glGetUniformLocation(composite_program_, "depth"), 1);
  glUniform2f(glGetUniformLocation(composite_program_, "origin"), static_cast<float>(x0), 0.0f);
  glUniform2f(glGetUniformLocation(composite_program_, "size"), static_cast<float>(width),
              static_cast<float>(height));
  glDepthFunc(GL_ALWAYS);
  glBindVertexArray(gizmo_vao_);  // any VAO: the triangle's corners come from gl_VertexID
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glDepthFunc(GL_LESS);
  glBindTexture(GL_TEXTURE_2D, 0);
  if (gizmo_) DrawGizmo(scene.vp);
  glBindVertexArray(0);
  glUseProgram(0);
  drawn_segments_ = refined_;
  return refined_ >= scene.segments;
}

void Viewer::DrawGizmo(const Eigen::Matrix4f& vp) {
  const CutRegion& r = *gizmo_;
  if (r.kind == CutRegion::Kind::kMaxLength) return;
  std::vector<Eigen::Vector3f> fill, lines;
  const float size = bounds_.isEmpty() ? 0.3f : 0.6f * bounds_.diagonal().norm();
  if (r.kind == CutRegion::Kind::kAbovePlane) {
    // A square of the plane around the point of the plane closest to the box's centre.
    const Eigen::Vector3f n = r.normal.normalized().cast<float>();
    const Eigen::Vector3f c0 = Centre();
    const Eigen::Vector3f c = c0 - (n.dot(c0) - static_cast<float>(r.offset)) * n;
    const Eigen::Vector3f a =
        (std::abs(n.x()) < 0.9f ? Eigen::Vector3f::UnitX() : Eigen::Vector3f::UnitY())
            .cross(n)
            .normalized();
    const Eigen::Vector3f b = n.cross(a);
    const float h = 0.5f * size;
    const Eigen::Vector3f q[4] = {c - h * a - h * b, c + h * a - h * b, c + h * a + h * b,
                                  c - h * a + h * b};
    fill = {q[0], q[1], q[2], q[0], q[2], q[3]};
    for (int k = 0; k < 4; ++k) {
      lines.push_back(q[k]);
      lines.push_back(q[(k + 1) % 4]);
    }
    // The normal: an arrow toward the kept side.
    lines.push_back(c);
    lines.push_back(c + 0.15f * size * n);
  } else {
    // A sphere's wire frame: 12 meridians and 7 parallels.
    const Eigen::Vector3f c = r.centre.cast<float>();
    const float radius = static_cast<float>(r.radius);
    const int m = 48;
    const float pi = static_cast<float>(std::acos(-1.0));
    const auto point = [&](float theta, float phi) {
      return Eigen::Vector3f(c + radius * Eigen::Vector3f(std::sin(theta) * std::cos(phi),
                                                          std::sin(theta) * std::sin(phi),
                                                          std::cos(theta)));
    };
    for (int k = 0; k < 12; ++k) {
      const float phi = 2.0f * pi * k / 12;
      for (int j = 0; j < m; ++j) {
        lines.push_back(point(pi * j / m, phi));
        lines.push_back(point(pi * (j + 1) / m, phi));
      }
    }
    for (int k = 1; k < 8; ++k) {
      const float theta = pi * k / 8;
      for (int j = 0; j < m; ++j) {
        lines.push_back(point(theta, 2.0f * pi * j / m));
        lines.push_back(point(theta, 2.0f * pi * (j + 1) / m));
      }
    }
  }
  std::vector<float> data;
  for (const auto* list : {&fill, &lines}) {
    for (const Eigen::Vector3f& p : *list) data.insert(data.end(), {p.x(), p.y(), p.z()});
  }
  glUseProgram(gizmo_program_);
  SetMatrix(gizmo_program_, "view_projection", vp);
  glBindVertexArray(gizmo_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, gizmo_vbo_);
  glBufferData(GL_ARRAY_BUFFER, data.size() * sizeof(float), data.data(), GL_STREAM_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDepthMask(GL_FALSE);
  const GLint colour = glGetUniformLocation(gizmo_program_, "colour");
  if (!fill.empty()) {
    glUniform4f(colour, 1.0f, 0.35f, 0.2f, 0.3f);
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(fill.size()));
  }
  glUniform4f(colour, 1.0f, 0.55f, 0.2f, 0.9f);
  glDrawArrays(GL_LINES, static_cast<GLsizei>(fill.size()), static_cast<GLsizei>(lines.size()));
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
}

std::vector<int> Viewer::PickRoots(const OrbitCamera& camera, int x0, int full_width, int height,
                                   float x, float y, float radius) const {
  const int width = std::max(1, full_width - x0);
  x -= static_cast<float>(x0);
  std::vector<int> picked;
  if (!hair_) return picked;
  const Eigen::Matrix4f vp =
      camera.Projection(static_cast<float>(width) / std::max(1, height)) * camera.View();
  const Eigen::Vector3f eye = camera.Position();
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  if (const auto* s = std::get_if<SphereScalp>(&hair_->styled.style.scalp)) {
    centre = s->head.centre.cast<float>();
  }
  const std::vector<Root>& roots = hair_->styled.masters.roots;
  for (int i = 0; i < static_cast<int>(roots.size()); ++i) {
    const Eigen::Vector3f p = roots[i].position.cast<float>();
    if ((p - centre).dot(eye - p) <= 0.0f) continue;  // behind the head
    const Eigen::Vector4f clip = vp * Eigen::Vector4f(p.x(), p.y(), p.z(), 1.0f);
    if (clip.w() <= 0.0f) continue;
    const float sx = (clip.x() / clip.w() * 0.5f + 0.5f) * width;
    const float sy = (0.5f - clip.y() / clip.w() * 0.5f) * height;
    if ((sx - x) * (sx - x) + (sy - y) * (sy - y) <= radius * radius) picked.push_back(i);
  }
  return picked;
}

}  // namespace ringlet::studio
