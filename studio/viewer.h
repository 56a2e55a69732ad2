// The studio's OpenGL 3.3 view of a hairstyle: the body (spheres and meshes, lit) and every
// strand as a camera-facing ribbon of the fibre's width (expanded in a geometry shader), shaded
// with Kajiya-Kay plus two shifted highlights (Marschner's R and TRT), coloured from melanin.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "ringlet/body.h"
#include "ringlet/render_json.h"
#include "session.h"

namespace ringlet::studio {

/// The fixed views of the view keys (docs/studio.md): the head's conventions of the hairstyle
/// format, z up and the face toward +y (so the head's right is +x).
enum class ViewSide : std::uint8_t { kFront, kBack, kRight, kLeft, kTop, kBottom };

/// Orbit camera: looks at target from yaw / pitch (rad) at distance (m). The camera sits at
/// target + distance (sin yaw cos pitch, -cos yaw cos pitch, sin pitch): yaw = 0 looks along +y
/// from the -y side (at the back of a head whose face is toward +y), yaw = pi at the face.
struct OrbitCamera {
  Eigen::Vector3f target = Eigen::Vector3f(0.0f, 0.0f, -0.05f);
  float yaw = 3.1415927f;  ///< around +z (rad); pi = in front of the face (+y side)
  float pitch = 0.15f;     ///< elevation (rad), in [-kMaxPitch, kMaxPitch]
  float distance = 0.9f;
  float fov = 0.6f;  ///< vertical field of view (rad)

  Eigen::Vector3f Position() const;
  Eigen::Matrix4f View() const;
  Eigen::Matrix4f Projection(float aspect) const;
  void Orbit(float dyaw, float dpitch);
  /// Turns the camera so that it sits in this direction from the target (any length; yaw and
  /// pitch from it, the pitch clamped), keeping the target and distance.
  void LookFrom(const Eigen::Vector3f& direction);
  /// One of the fixed views (front: yaw pi, pitch 0; right: yaw pi/2; back: 0; left: -pi/2;
  /// top / bottom: pitch +-kMaxPitch, the face toward the bottom / top of the screen).
  void SetView(ViewSide side);
  static constexpr float kMaxPitch = 1.5f;  ///< rad: the view's up (+z) stays defined
  /// Moves the target in the view plane by (dx, dy) in units of the distance.
  void Pan(float dx, float dy);
  void Zoom(float factor);
  /// Frames the box (its bounding sphere fills the view).
  void Frame(const Eigen::AlignedBox3f& box);
};

/// What the hair looks like.
struct HairLook {
  Eigen::Vector3f colour = Eigen::Vector3f(0.25f, 0.15f, 0.08f);  ///< linear RGB of the fibres
  bool masters_only = false;                                      ///< draw the master strands alone
  bool highlight_masters = false;
  /// The light comes from the camera (a headlight) instead of the fixed key light below.
  bool headlight = false;
  /// Toward the fixed key light: the hairstyle's render key light (RenderSettings::key).
  Eigen::Vector3f key_light = Eigen::Vector3f(-0.4f, 0.8f, 1.0f).normalized();
};

/// The base colour of hair with these melanins: exp(-3 sigma_a) of Chiang's absorption
/// (AbsorptionFromMelanin; two passes through the fibre, the TT/TRT path), a simple mapping.
Eigen::Vector3f MelaninColour(double eumelanin, double pheomelanin);

/// The colour the path tracer gives hair of these render settings (melanins, fibre optics, key
/// light, environment, exposure) and eccentricity: the mean linear radiance of a small render
/// (12 x 12 pixels, 8 samples, not denoised; 0.1-0.2 s on 2 shared cores) of an opaque swatch
/// of parallel fibres seen from the front, times the exposure. Falls back to MelaninColour when
/// the render fails.
Eigen::Vector3f PathTracedHairColour(const RenderSettings& settings, double eccentricity);

class Viewer {
 public:
  Viewer();
  ~Viewer();
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  /// Creates the GL objects (a current 3.3 core context is required). False with a message.
  bool Init(std::string* error);
  /// Uploads the strands of a hair state (one VBO, one index buffer for all strands, one for
  /// the masters) and the body.
  void SetHair(const std::shared_ptr<const HairState>& hair);
  /// The masters being solved (Session::Preview), drawn instead of the hair while set (null:
  /// the hair again). Kept in buffers of their own: the hair's stay on the GPU, so that the
  /// solve's result uploads only its regrown wisps.
  void SetPreview(const std::shared_ptr<const HairState>& preview);
  /// Marks the brushed masters (highlighted) and re-uploads the per-vertex flags.
  void SetBrush(const std::vector<int>& masters);
  /// Draws into the current framebuffer of full_width x height pixels, the 3D view in the
  /// columns from x0 on (the panel covers the left). With max_segments >= 0 (the preview
  /// density while the camera moves or a solve runs) only the first max_segments segments of
  /// the drawing order are drawn: the masters first, then the first child of every wisp, the
  /// second, ... (wisps in a well-spread order), so that any prefix is the masters and an even
  /// subset of the children; and the body is drawn coarse (vertex clustering: about a sixth of
  /// its triangles). Hair thinner than a pixel is drawn as lines, else as ribbons (a geometry
  /// shader): the same picture, the lines cheaper (viewer.cpp).
  void Draw(const OrbitCamera& camera, const HairLook& look, int x0, int full_width, int height,
            long max_segments = -1);
  /// Full density without holding the UI: the picture is drawn off screen, chunk segments (in
  /// the drawing order) per call, and shown as far as it got (with the gizmo on top); a change
  /// of the camera, the look, the hair or the view's size starts it again. True once every
  /// segment is in it (the picture equals Draw's at full density, without multisampling).
  bool DrawRefining(const OrbitCamera& camera, const HairLook& look, int x0, int full_width,
                    int height, long chunk);
  /// The box of the hair and body (for frame-all).
  const Eigen::AlignedBox3f& Bounds() const { return bounds_; }
  /// Masters whose roots are within radius pixels of (x, y) (pixels, top-left origin) and face
  /// the camera.
  std::vector<int> PickRoots(const OrbitCamera& camera, int x0, int full_width, int height, float x,
                             float y, float radius) const;
  /// The cut region to show over the hair (a translucent plane, or a sphere's wire frame),
  /// or none: what the cut tool will apply.
  void SetGizmo(const std::optional<CutRegion>& region) { gizmo_ = region; }
  /// The centre of the hair and body box and its radius (m): where the plane gizmo is drawn.
  Eigen::Vector3f Centre() const {
    return bounds_.isEmpty() ? Eigen::Vector3f(Eigen::Vector3f::Zero())
                             : Eigen::Vector3f(bounds_.center());
  }
  /// Number of segments drawn by the last Draw.
  long DrawnSegments() const { return drawn_segments_; }
  /// Segments drawn by the last Draw or DrawRefining call itself (a refining call: its chunk).
  long LastDrawSegments() const { return last_draw_segments_; }
  /// Segments of all strands, and of the masters alone.
  long TotalSegments() const { return Shown().indices / 2; }
  long MasterSegments() const { return Shown().master_indices / 2; }
  /// Triangles of the body, and of its coarse version (drawn while the camera moves).
  long BodyTriangles() const { return body_vertices_ / 3; }
  long CoarseBodyTriangles() const { return coarse_body_vertices_ / 3; }
  /// Whether the last Draw or DrawRefining drew the hair as lines (thinner than a pixel).
  bool DrewLines() const { return drew_lines_; }
  /// Bytes sent to the GPU by the last SetHair (all buffers, or the regrown wisps only).
  long LastUploadBytes() const { return last_upload_bytes_; }

 private:
  // Strands on the GPU: points (position, width), tangents (3 normalized bytes + pad), flags,
  // and the segments' indices in drawing order (the masters the first master_indices).
  struct StrandBuffers {
    unsigned vao = 0, vbo = 0, tangent_vbo = 0, flag_vbo = 0, ebo = 0;
    long indices = 0, master_indices = 0;
    float max_width = 0.0f;  // m
  };
  // What a frame draws with (Draw, DrawRefining).
  struct Scene {
    Eigen::Matrix4f vp;
    Eigen::Vector3f eye, light;
    float pixels_per_unit = 1.0f;
    long segments = 0;  // of the look (masters only, or all)
    const StrandBuffers* strands = nullptr;
    const std::variant<SphereScalp, MeshScalp>* scalp = nullptr;  // of the strands drawn
    bool lines = false;            // every fibre thinner than a pixel: lines, not ribbons
  };
  Scene MakeScene(const OrbitCamera& camera, const HairLook& look, int width, int height) const;
  void DrawBody(const Scene& scene, bool coarse);
  void DrawHair(const Scene& scene, const HairLook& look, long first, long count);
  void UploadFlags();
  void DrawGizmo(const Eigen::Matrix4f& view_projection);
  void UploadBody(const Body& body);
  void UploadStrands(StrandBuffers* buffers, const HairCurves& curves,
                     const std::vector<std::uint32_t>& indices);
  void ExtendBounds(const HairCurves& curves);
  const StrandBuffers& Shown() const {
    return preview_ && preview_->strands ? preview_gl_ : hair_gl_;
  }

  std::shared_ptr<const HairState> hair_, preview_;
  const Body* body_ = nullptr;
  std::vector<int> brush_;
  unsigned hair_program_ = 0, line_program_ = 0, body_program_ = 0;
  StrandBuffers hair_gl_, preview_gl_;
  unsigned body_vao_ = 0, body_vbo_ = 0, coarse_body_vao_ = 0, coarse_body_vbo_ = 0;
  long body_vertices_ = 0, coarse_body_vertices_ = 0;
  bool drew_lines_ = false;
  std::vector<std::uint32_t> strand_of_master_;  // first strand of each wisp
  Eigen::AlignedBox3f bounds_;
  long drawn_segments_ = 0, last_draw_segments_ = 0;
  long last_upload_bytes_ = 0;
  std::optional<CutRegion> gizmo_;
  unsigned gizmo_program_ = 0, gizmo_vao_ = 0, gizmo_vbo_ = 0;
  // DrawRefining's off-screen picture, the segments in it (-1: none) and what it shows.
  unsigned composite_program_ = 0, refine_fbo_ = 0, refine_colour_ = 0, refine_depth_ = 0;
  int refine_width_ = 0, refine_height_ = 0;
  long refined_ = -1;
  std::vector<float> refine_key_;
  std::uint64_t hair_version_ = 0;  // counts uploads of strands and flags
};

}  // namespace ringlet::studio
