// `ringlet-studio [HAIRSTYLE.json] [--script FILE] [--screenshot OUT.png] [--size WxH]
// [--report FILE] [--min-frame-seconds S]`: the interactive hairstyling tool (docs/studio.md). A
// window with the hair and body (viewer.h), an ImGui panel of controls in groomers' vocabulary, a
// brush on the scalp, and the editing model (session.h) re-solving on a worker thread. --script
// runs a line-based script (below) and exits: the headless mode of the tests, under xvfb-run.
// HAIRSTYLE --screenshot OUT.png without --script saves the first solved frame and exits.
//
// Input: GLFW's callbacks queue every event (InputEvent); each frame takes a run of them with at
// most one button or key transition (TakeFrameEvents), so that a click or key tap shorter than a
// frame is seen by ImGui and by the view, at the cursor position of the event. Drags are
// measured from the press; shortcuts act once per press (GLFW_PRESS, never on key repeat). The
// window redraws only when something changed (an event, a solve's progress or result, a render
// pass): idle, it sleeps in glfwWaitEvents.
//
// Script commands, one per line (# comments): open PATH | new | set FIELD VALUE |
// brush X Y RADIUS | brush-clear | brush-spread N (N masters evenly spread over the indices) |
// curl R P | cut-z Z | cut-plane NX NY NZ D | cut-length L | cut-sphere X Y Z R | wet | dry |
// grow STEP STEPS (every operation acts on the brushed masters, when any) |
// gizmo plane HEIGHT TILT ROLL | gizmo sphere X Y Z R | gizmo off | gizmo-drag DY (pixels) |
// cut-gizmo (applies the gizmo's cut) | undo | redo | orbit DYAW DPITCH | zoom FACTOR | frame |
// masters on|off | wait | screenshot PATH | save PATH [force] | export PATH [force] |
// render WIDTH SPP (the render panel, waits for the last pass) | save-render PATH [force] |
// frames N (draw N frames, prints the mean frame time) | bench-wait (after an edit: blocks for
// the worker, then uploads and draws once, printing where the time went) | memory.
#include <epoxy/gl.h>
// GLFW after the GL loader.
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <imgui_internal.h>  // ImGuiWindow::ContentSize, for --report only

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <future>
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "ringlet/atomic_file.h"
#include "ringlet/png_image.h"
#include "ringlet/render.h"
#include "ringlet/render_json.h"
#include "ringlet/strand_export.h"
#include "ringlet/strand_geometry.h"
#include "brush_tool.h"
#include "session.h"
#include "viewer.h"

namespace ringlet::studio {
namespace {

// The panel's default width and the width of the document's sliders, in units of the font size
// (em): every label, and the wisp radius' "auto" button after its label, fit in the panel at
// its default width (the input tests check it), which is therefore also its narrowest. The panel
// is resizable (drag its right edge) up to all but kMinViewPixels of the window; its width is
// the session's (App::panel_width, kept when another file is opened), not the document's.
constexpr float kPanelEm = 30.0f;
constexpr float kMinPanelEm = kPanelEm;
constexpr float kMinViewPixels = 200.0f;
constexpr float kFieldEm = 13.0f;
// The UI font: Debian's DejaVu Sans (fonts-dejavu-core) at this size (pixels); ImGui's own
// font (ProggyClean, 13 px) when the file is missing.
constexpr const char* kFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
constexpr float kFontPixels = 15.0f;
// The preview density (docs/studio.md): while the camera moves, a solve runs, or new hair has
// just arrived, the hair is drawn at most preview_budget segments (the masters first); full
// density once nothing moved for kStillSeconds. The budget follows the measured drawing rate so
// that the hair's draw takes about kPreviewSeconds, within [kMinPreview, kMaxPreview] segments.
constexpr double kStillSeconds = 0.35;
constexpr double kPreviewSeconds = 0.05;
constexpr long kMinPreview = 10000, kMaxPreview = 200000, kFirstPreview = 50000;

float FieldWidth() { return kFieldEm * ImGui::GetFontSize(); }

// One input event, queued by GLFW's callbacks in the order the window system delivered them.
struct InputEvent {
  enum class Kind : std::uint8_t { kMove, kButton, kScroll, kKey, kChar };
  Kind kind = Kind::kMove;
  double x = 0.0, y = 0.0;  // cursor (window coordinates) of kMove and kButton; kScroll offsets
  int code = 0;             // the button, the key (GLFW_KEY_*) or the character
  int action = 0;           // GLFW_PRESS, GLFW_RELEASE or GLFW_REPEAT
  int mods = 0;             // GLFW_MOD_* at the event
};

// A drag in the view, measured from the press (not from the previous frame's cursor).
struct ViewDrag {
  enum class Mode : std::uint8_t { kNone, kOrbit, kPan, kBrush, kGizmo, kSculpt };
  Mode mode = Mode::kNone;
  int button = -1;
  double x0 = 0.0, y0 = 0.0;  // the press (window coordinates)
  int mods = 0;               // at the press
  OrbitCamera camera;         // at the press
  float plane_height = 0.0f, plane_tilt = 0.0f, plane_roll = 0.0f;
  float sphere_centre_z = 0.0f, sphere_radius = 0.0f;
};

// The value of the document slider being edited: while a slider is active it shows this value,
// not the document's, and its release commits it (the document changes once per edit).
struct FieldEdit {
  unsigned id = 0;  // ImGuiID of the active slider, 0 for none
  double value[3] = {0.0, 0.0, 0.0};
  int int_value = 0;
};

// The render panel: the path tracer (render.h) with the studio's camera on a worker thread,
// progressive (RenderOptions::pass_done: 1, 2, 4, ... samples per pixel, each pass shown as it
// arrives), cancellable (RenderOptions::cancel).
struct RenderPanel {
  bool open = false;
  int width = 320;  // pixels; the height follows the view's aspect
  int spp = 16;
  std::thread thread;
  std::atomic<bool> cancel{false};
  std::atomic<bool> running{false};
  std::atomic<long> tiles_done{0}, tiles_total{0};
  std::mutex mutex;  // guards image, samples, dirty, error, seconds
  Image image;
  int samples = 0;
  bool dirty = false;
  std::string error;
  double seconds = 0.0;
  // UI thread: the pass shown and its texture.
  Image shown;
  int shown_samples = 0;
  unsigned texture = 0;
  char png_path[512] = "render.png";

  void Stop() {
    cancel = true;
    if (thread.joinable()) thread.join();
    cancel = false;
  }
  ~RenderPanel() { Stop(); }
};

// What waits for the user's answer in a modal.
enum class Guarded { kNone, kOpen, kNew, kQuit };  // drops unsaved changes
enum class Write { kNone, kSave, kExport, kPng };   // replaces an existing file

struct App {
  Session session;
  Viewer viewer;
  OrbitCamera camera;
  HairLook look;
  GLFWwindow* window = nullptr;
  std::shared_ptr<const HairState> uploaded, previewed;  // given to the viewer
  std::pair<const HairState*, const HairState*> viewer_hair{nullptr, nullptr};
  std::string message;  // the last error or notice, shown in the panel
  float panel_width = 0.0f;  // window coordinates; 0 until the first frame (kPanelEm)
  float panel_content_width = 0.0f, panel_inner_width = 0.0f;  // --report
  // The preview density: when the camera or the hair last changed (glfwGetTime), the camera of
  // the last frame, whether the last frame was a preview, the segments drawn per second
  // (measured on frames of at least kMinPreview segments; 0 until then) and the budget.
  bool allow_preview = true;  // interactive only: scripts and screenshots draw full density
  double last_motion = -1e9;
  OrbitCamera drawn_camera;
  bool preview_shown = false;
  bool refining = false;  // the full-density picture is still being drawn (DrawRefining)
  double segments_per_second = 0.0;
  long preview_budget = kFirstPreview;
  double draw_seconds = 0.0;    // the last frame's hair and body (with glFinish)
  long fixed_preview = -1;      // --preview-segments: a fixed budget instead of the measured one
  bool screenshot_key = false;  // F12 pressed: save this frame as studio-NNN.png
  bool brush_mode = false;
  float brush_radius = 30.0f;
  bool brush_only = true;  // operations act on the brushed masters only (when any)
  // The sculpting brushes (brush_tool.h; docs/studio.md, "Brushes"): 0 off, 1 comb (drag the
  // hair where it should lie: a sculpt operation, held there by inverse statics), 2 puff (click
  // the head: the roots under the brush stand up; Shift flattens). One operation per stroke.
  int sculpt_tool = 0;
  // 4 length (click the hair: shorten; Shift lengthens), 5 clump (Shift unclumps), 6 frizz
  // (Shift smooths): one operation per click, at the hair under the brush or the head.
  float sculpt_radius_mm = 30.0f, sculpt_strength = 0.5f, puff_degrees = 15.0f;
  float length_factor = 0.8f, clump_factor = 0.6f, frizz_mm = 3.0f;
  int sculpt_falloff = 0;  // Brush::Falloff: smooth, linear, constant
  bool sculpt_mirror = true;
  // The parting line being drawn on the head (tool 3): its two ends so far.
  std::optional<Vec3> parting_from;
  Vec3 parting_to = Vec3::Zero();
  // The comb stroke being dragged: its start on the hair, where the press ray met the view
  // plane through it, the camera's forward axis at the press, and its end so far.
  std::optional<Vec3> stroke_from;
  Vec3 stroke_anchor = Vec3::Zero(), stroke_view = Vec3::UnitY(), stroke_to = Vec3::Zero();
  bool framed = false;
  // Operation parameters of the panel.
  float curl_radius_mm = 8.0f, curl_pitch_mm = 20.0f;
  float cut_z = -0.15f, cut_length = 0.2f;
  float grow_step_mm = 10.0f;
  int grow_steps = 2;
  char path[512] = "";
  char save_path[512] = "styled.json";
  char export_path[512] = "styled.hair";
  double last_edit_time = 0.0;  // when the last edit was made (s, glfwGetTime)
  double last_latency = 0.0;    // edit to hair on screen (s)
  double last_upload = 0.0;     // of which uploading the strands (s)
  // The cut tool: 0 off, 1 plane, 2 sphere; the region is shown in the view and applied by
  // "Apply cut" (or Enter). Dragging in the view (left button) moves the plane up/down or
  // grows the sphere; with shift it tilts the plane or moves the sphere up/down.
  int cut_tool = 0;
  float plane_height = -0.12f, plane_tilt = 0.0f, plane_roll = 0.0f;  // m, degrees
  float sphere_centre[3] = {0.0f, 0.0f, 0.0f};
  float sphere_radius = 0.2f;
  RenderSettings render_settings;
  bool look_computed = false;  // look.colour is the path tracer's for render_settings
  RenderPanel render;
  // Modals.
  Guarded guarded = Guarded::kNone;
  std::string guarded_path;
  bool ask_unsaved = false;
  Write replace = Write::kNone;
  std::string replace_path;
  bool ask_replace = false;
  bool quit = false;
  // Input (the event queue, and the state ImGui is given each frame).
  std::vector<InputEvent> events;
  double cursor_x = 0.0, cursor_y = 0.0;  // after the events taken so far
  bool mouse_down[5] = {false, false, false, false, false};
  bool keys_down[512] = {};
  ViewDrag drag;
  FieldEdit edit;
  int redraw_frames = 2;  // frames still to draw before waiting for events
  double min_frame_seconds = 0.0;  // --min-frame-seconds (tests of input at low frame rates)
  // --report: after each frame, the widgets' rectangles and the document as JSON.
  std::string report_path;
  std::string last_report;
  // Startup phases (wall and process CPU seconds since launch) and the last frame's CPU time
  // (the process's, llvmpipe's threads included), for the report and the bench.
  nlohmann::ordered_json startup = nlohmann::ordered_json::object();
  double frame_cpu_seconds = 0.0;
  bool first_hair_timed = false;
  int window_size[2] = {0, 0}, framebuffer_size[2] = {0, 0};  // RefreshSizes
  bool sizes_read = false;
  long frames = 0;
  nlohmann::ordered_json widgets = nlohmann::ordered_json::object();
};

// The window's size and its framebuffer's as of this frame (read at the start of each frame,
// RefreshSizes): on X11 each glfwGet*Size is a round trip to the server (XGetWindowAttributes),
// and a frame asked for several per widget and per master tip of the --report.
void RefreshSizes(App* app) {
  glfwGetWindowSize(app->window, &app->window_size[0], &app->window_size[1]);
  glfwGetFramebufferSize(app->window, &app->framebuffer_size[0], &app->framebuffer_size[1]);
  app->sizes_read = true;
}

void WindowSize(App* app, int* w, int* h) {
  if (!app->sizes_read) RefreshSizes(app);
  *w = app->window_size[0];
  *h = app->window_size[1];
}

void FramebufferSize(App* app, int* w, int* h) {
  if (!app->sizes_read) RefreshSizes(app);
  *w = app->framebuffer_size[0];
  *h = app->framebuffer_size[1];
}

// The panel's width in framebuffer pixels (the 3D view is to its right).
int PanelPixels(App* app) {
  int ww, wh, fw, fh;
  WindowSize(app, &ww, &wh);
  FramebufferSize(app, &fw, &fh);
  return static_cast<int>(app->panel_width * (ww > 0 ? static_cast<float>(fw) / ww : 1.0f));
}

void Report(App* app, const std::string& text) {
  app->message = text;
  std::fprintf(stderr, "ringlet-studio: %s\n", text.c_str());
}

void Edited(App* app) { app->last_edit_time = glfwGetTime(); }

// User + system CPU time of the process (all threads: the solver's, llvmpipe's), s.
double ProcessCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Wall time since the process started (s).
double SinceLaunch() {
  static const auto launch = std::chrono::steady_clock::now();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - launch).count();
}

// Records a startup phase's end: [wall, CPU] seconds since launch (the report's "startup").
void Phase(App* app, const char* name) {
  app->startup[name] = {SinceLaunch(), ProcessCpuSeconds()};
}

void LoadLook(App* app, const std::string& path) {
  RenderSettings settings;
  std::string error;
  if (path.empty() || !LoadRenderSettings(path, &settings, &error)) settings = RenderSettings();
  const bool same_look = app->look_computed &&
                         settings.eumelanin == app->render_settings.eumelanin &&
                         settings.pheomelanin == app->render_settings.pheomelanin &&
                         settings.exposure == app->render_settings.exposure;
  app->render_settings = settings;
  app->look.key_light = settings.key.direction.cast<float>().normalized();
  if (same_look) return;
  app->look_computed = true;
  // The path tracer's colour of this hair (what the render panel shows), not a mapping of the
  // melanins; doubled because the view's shading ((0.15 + 0.85 diffuse) x ambient occlusion,
  // viewer.cpp) gives about half of the base colour where the light falls across the hair.
  app->look.colour = (2.0f * PathTracedHairColour(settings, 0.0)).cwiseMax(0.01f).cwiseMin(1.0f);
}

bool Open(App* app, const Session::File& file) {
  const std::string& path = file.path;
  std::string error;
  if (!app->session.Open(file, &error)) {
    Report(app, error);
    return false;
  }
  std::snprintf(app->path, sizeof(app->path), "%s", path.c_str());
  app->session.brush.clear();
  app->framed = false;
  LoadLook(app, path);
  app->message = "grooming " + path;
  Edited(app);
  return true;
}

bool Open(App* app, const std::string& path) { return Open(app, Session::Read(path)); }

void AddOperation(App* app, const StyleOperation& op) {
  std::string error;
  if (!app->session.AddOperation(op, &error)) {
    Report(app, error);
    return;
  }
  app->message.clear();
  Edited(app);
}

void SetField(App* app, const std::string& field, const nlohmann::ordered_json& value) {
  std::string error;
  if (!app->session.SetParameter(field, value, &error)) {
    Report(app, error);
    return;
  }
  app->message.clear();
  Edited(app);
}

// Every operation acts on the brushed masters when there are any (and the box is ticked).
StyleOperation Brushed(App* app, StyleOperation op) {
  if (app->brush_only && !app->session.brush.empty()) op.selection.indices = app->session.brush;
  return op;
}

StyleOperation Curl(App* app, double radius, double pitch) {
  StyleOperation op;
  op.kind = StyleOperation::Kind::kCurl;
  op.curl_radius = radius;
  op.curl_pitch = pitch;
  return Brushed(app, op);
}

StyleOperation CutZ(double z) {
  StyleOperation op;
  op.kind = StyleOperation::Kind::kCut;
  op.cut_region.offset = z;
  return op;
}

// The cut tool's region: the plane n . r >= height with n = +z tilted by `tilt` about x and
// `roll` about y (degrees), or the sphere.
CutRegion GizmoRegion(const App* app) {
  CutRegion r;
  if (app->cut_tool == 2) {
    r.kind = CutRegion::Kind::kInsideSphere;
    r.centre = Vec3(app->sphere_centre[0], app->sphere_centre[1], app->sphere_centre[2]);
    r.radius = app->sphere_radius;
    return r;
  }
  const double deg = std::numbers::pi / 180.0;
  const double t = app->plane_tilt * deg, q = app->plane_roll * deg;
  r.kind = CutRegion::Kind::kAbovePlane;
  r.normal = Vec3(std::sin(q) * std::cos(t), -std::sin(t), std::cos(q) * std::cos(t));
  // The plane passes through (0, 0, height) (the head's vertical axis at that height).
  r.offset = r.normal.z() * app->plane_height;
  return r;
}

// A vertical drag of dy pixels on the gizmo: the plane moves down (or the sphere grows) by the
// distance one pixel spans at the camera's target, so the plane follows the mouse.
void DragGizmo(App* app, float dx, float dy, bool shift) {
  int w, h;
  FramebufferSize(app, &w, &h);
  const float metres_per_pixel =
      2.0f * app->camera.distance * std::tan(0.5f * app->camera.fov) / std::max(1, h);
  if (app->cut_tool == 1) {
    if (shift) {
      app->plane_tilt = std::clamp(app->plane_tilt + 0.3f * dy, -80.0f, 80.0f);
      app->plane_roll = std::clamp(app->plane_roll + 0.3f * dx, -80.0f, 80.0f);
    } else {
      app->plane_height -= dy * metres_per_pixel;
    }
  } else if (app->cut_tool == 2) {
    if (shift) {
      app->sphere_centre[2] -= dy * metres_per_pixel;
    } else {
      app->sphere_radius = std::max(0.01f, app->sphere_radius + dy * metres_per_pixel);
    }
  }
}

StyleOperation Simple(StyleOperation::Kind kind) {
  StyleOperation op;
  op.kind = kind;
  return op;
}

// The view a file opens with: the hairstyle's render camera (render.camera, docs/rendering.md)
// when it places one (position and look_at: that camera, its field of view), else the render's
// framed camera (render.camera.view_direction, by default from the face's front right, slightly
// above): the hair and body framed, seen along that direction. Either way the face.
void OpeningView(App* app) {
  const CameraSettings& c = app->render_settings.camera;
  if (c.kind == CameraSettings::Kind::kExplicit) {
    const Eigen::Vector3f position = c.position.cast<float>(), look_at = c.look_at.cast<float>();
    app->camera.target = look_at;
    app->camera.distance = std::max(0.02f, (position - look_at).norm());
    app->camera.fov = static_cast<float>(c.vertical_fov);
    app->camera.LookFrom(position - look_at);
  } else {
    app->camera.Frame(app->viewer.Bounds());
    app->camera.LookFrom(-c.view_direction.cast<float>());
  }
}

// Takes a finished solve into the view.
void Sync(App* app) {
  app->session.Poll();
  // Before the first hair of a file is shown: the masters as they are solved (Session::Preview).
  std::shared_ptr<const HairState> hair = app->session.Hair();
  if (!hair) {
    if (auto preview = app->session.Preview()) hair = std::move(preview);
  }
  if (hair != app->uploaded) {
    const double upload_start = glfwGetTime();
    app->viewer.SetHair(hair);
    app->last_upload = glfwGetTime() - upload_start;
    app->viewer.SetBrush(app->session.brush);
    app->uploaded = hair;
    if (app->last_edit_time > 0.0 && hair) {
      app->last_latency = glfwGetTime() - app->last_edit_time;
    }
  }
  // While a solve runs: the masters as they are solved (Session::Preview; a fresh file's, or an
  // edit's that takes longer than the preview period), drawn instead of the hair.
  const std::shared_ptr<const HairState> preview = app->session.Preview();
  if (preview != app->previewed) {
    app->viewer.SetPreview(preview);
    app->previewed = preview;
  }
  if (app->viewer_hair != std::pair{hair.get(), preview.get()}) {
    app->viewer_hair = {hair.get(), preview.get()};
    if (!app->framed && (hair || preview)) {
      OpeningView(app);
      app->framed = true;
    }
    app->last_motion = glfwGetTime();  // new hair: a preview first, full density when still
    app->redraw_frames = std::max(app->redraw_frames, 2);
  }
  const std::string error = app->session.LastError();
  if (!error.empty()) app->message = error;
}

void Brush(App* app, float x, float y, bool erase) {
  int w, h;
  FramebufferSize(app, &w, &h);
  const std::vector<int> picked =
      app->viewer.PickRoots(app->camera, PanelPixels(app), w, h, x, y, app->brush_radius);
  std::vector<int>& brush = app->session.brush;
  for (int i : picked) {
    const auto it = std::find(brush.begin(), brush.end(), i);
    if (erase && it != brush.end()) brush.erase(it);
    if (!erase && it == brush.end()) brush.push_back(i);
  }
  std::sort(brush.begin(), brush.end());
  app->viewer.SetBrush(brush);
}

// ---------------------------------------------------------------------------------------------
// The render panel

// Starts rendering the shown hair with the studio's camera (cancelling a render in flight).
bool StartRender(App* app) {
  const auto hair = app->session.Hair();
  if (!hair || !hair->strands) {
    Report(app, "render: no hair to render yet");
    return false;
  }
  RenderPanel& r = app->render;
  r.Stop();
  RenderSettings settings = app->render_settings;
  int fw, fh;
  FramebufferSize(app, &fw, &fh);
  const int view_w = std::max(1, fw - PanelPixels(app)), view_h = std::max(1, fh);
  settings.options.width = r.width;
  settings.options.height =
      std::max(1, static_cast<int>(std::lround(r.width * static_cast<double>(view_h) / view_w)));
  settings.options.samples_per_pixel = r.spp;
  // The view's camera (OrbitCamera: up is +z, fov vertical).
  Camera camera;
  camera.position = app->camera.Position().cast<double>();
  camera.look_at = app->camera.target.cast<double>();
  camera.up = Vec3::UnitZ();
  camera.vertical_fov = app->camera.fov;
  {
    std::lock_guard<std::mutex> lock(r.mutex);
    r.error.clear();
    r.samples = 0;
    r.seconds = 0.0;
  }
  r.tiles_done = 0;
  r.tiles_total = 0;
  r.running = true;
  r.open = true;
  r.thread = std::thread([&r, hair, settings, camera] {
    const Hairstyle& style = hair->styled.style;
    RenderScene scene;
    std::string error;
    bool ok = MakeRenderScene(settings, hair->strands.get(), style.body,
                              HairTypeEccentricity(style.hair_type), style.seed, &scene, &error);
    RenderStats stats;
    Image final_image;
    if (ok) {
      scene.camera = camera;
      RenderOptions options = settings.options;
      options.cancel = &r.cancel;
      options.progress = [&r](long done, long total) {
        r.tiles_done = done;
        r.tiles_total = total;
      };
      options.pass_done = [&r](const Image& image, int samples) {
        std::lock_guard<std::mutex> lock(r.mutex);
        r.image = image;
        r.samples = samples;
        r.dirty = true;
      };
      ok = Render(scene, options, &final_image, &stats, &error);
    }
    {
      std::lock_guard<std::mutex> lock(r.mutex);
      if (ok) {
        // The final image: the last pass, denoised when the settings ask for it (render.h).
        r.image = std::move(final_image);
        r.dirty = true;
        r.seconds = stats.seconds;
      }
      if (!ok && error != "cancelled") r.error = "render: " + error;
    }
    r.running = false;
  });
  return true;
}

// Takes a finished pass into the panel's texture (sRGB bytes with the settings' exposure).
void SyncRender(App* app) {
  RenderPanel& r = app->render;
  {
    std::lock_guard<std::mutex> lock(r.mutex);
    if (!r.dirty) return;
    r.shown = r.image;
    r.shown_samples = r.samples;
    r.dirty = false;
  }
  app->redraw_frames = std::max(app->redraw_frames, 2);
  const Image& image = r.shown;
  const float exposure = static_cast<float>(app->render_settings.exposure);
  std::vector<unsigned char> bytes(static_cast<size_t>(image.width) * image.height * 4);
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const float x = std::clamp(image.pixels[i][c] * exposure, 0.0f, 1.0f);
      const float srgb = x <= 0.0031308f ? 12.92f * x : 1.055f * std::pow(x, 1.0f / 2.4f) - 0.055f;
      bytes[4 * i + c] = static_cast<unsigned char>(std::lround(255.0f * srgb));
    }
    bytes[4 * i + 3] = 255;
  }
  if (!r.texture) glGenTextures(1, &r.texture);
  glBindTexture(GL_TEXTURE_2D, r.texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, image.width, image.height, 0, GL_RGBA,
               GL_UNSIGNED_BYTE, bytes.data());
  glBindTexture(GL_TEXTURE_2D, 0);
}

// ---------------------------------------------------------------------------------------------
// Files: nothing is replaced or dropped without asking

bool Exists(const std::string& path) {
  std::error_code ec;
  return std::filesystem::exists(std::filesystem::symlink_status(path, ec));
}

// Writes a file of this kind (atomically; an existing one only when overwrite). Reports.
bool DoWrite(App* app, Write kind, const std::string& path, bool overwrite) {
  std::string error;
  bool ok = false;
  switch (kind) {
    case Write::kSave:
      ok = app->session.Save(path, &error, overwrite);
      break;
    case Write::kExport: {
      const auto hair = app->session.Hair();
      if (!hair || !hair->strands) {
        error = "export: no hair to export yet";
        break;
      }
      if (!app->session.UpToDate()) {
        error = "export: the hair is being re-solved; export when it is done";
        break;
      }
      // The document's render settings colour the strands: the bytes of `ringlet style` (and
      // `ringlet groom`) for the saved document, by the same library call.
      RenderSettings render;
      if (!ParseRenderMember(nlohmann::json(app->session.CurrentDocument().parameters), &render,
                             &error)) {
        break;
      }
      ok = ExportHairstyleStrands(path, *hair->strands, render, HairFileOptions{}, overwrite,
                                  &error);
      break;
    }
    case Write::kPng:
      if (app->render.shown.pixels.empty()) {
        error = "render: nothing rendered yet";
        break;
      }
      ok = WritePng(path, app->render.shown, app->render_settings.exposure, overwrite, &error);
      break;
    case Write::kNone:
      return false;
  }
  if (!ok) {
    Report(app, error);
    return false;
  }
  const char* what = kind == Write::kSave ? "saved " : kind == Write::kExport ? "exported " : "wrote ";
  app->message = what + path;
  return true;
}

// Writes, or asks first when the file exists.
void TryWrite(App* app, Write kind, const std::string& path) {
  if (Exists(path)) {
    app->replace = kind;
    app->replace_path = path;
    app->ask_replace = true;
    return;
  }
  DoWrite(app, kind, path, false);
}

void DoGuarded(App* app, Guarded action, const std::string& path) {
  switch (action) {
    case Guarded::kOpen:
      Open(app, path);
      break;
    case Guarded::kNew:
      app->session.New();
      app->viewer.SetHair(nullptr);
      app->viewer.SetPreview(nullptr);
      app->uploaded = app->previewed = nullptr;
      app->viewer.SetBrush({});
      app->message = "new: open a hairstyle to start";
      break;
    case Guarded::kQuit:
      app->quit = true;
      break;
    case Guarded::kNone:
      break;
  }
}

// Runs the action, or asks first when it would drop unsaved changes.
void Guard(App* app, Guarded action, const std::string& path = "") {
  if (app->session.Modified()) {
    app->guarded = action;
    app->guarded_path = path;
    app->ask_unsaved = true;
    return;
  }
  DoGuarded(app, action, path);
}

void Modals(App* app) {
  if (app->ask_unsaved) ImGui::OpenPopup("Unsaved changes");
  if (app->ask_replace) ImGui::OpenPopup("Replace file?");
  app->ask_unsaved = app->ask_replace = false;
  if (ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    const char* what = app->guarded == Guarded::kOpen  ? "Opening another hairstyle"
                       : app->guarded == Guarded::kNew ? "Starting a new session"
                                                       : "Quitting";
    ImGui::Text("The hairstyle has unsaved changes. %s drops them.", what);
    if (ImGui::Button("Save, then continue")) {
      const std::string path = app->session.Path().empty() ? app->save_path : app->session.Path();
      std::string error;
      // Its own file is replaced; another existing file is not (Save As asks).
      if (app->session.Save(path, &error, path == app->session.Path())) {
        DoGuarded(app, app->guarded, app->guarded_path);
      } else {
        Report(app, error);
      }
      app->guarded = Guarded::kNone;
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Discard changes")) {
      DoGuarded(app, app->guarded, app->guarded_path);
      app->guarded = Guarded::kNone;
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) {
      app->guarded = Guarded::kNone;
      ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
  }
  if (ImGui::BeginPopupModal("Replace file?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::Text("%s already exists.", app->replace_path.c_str());
    if (ImGui::Button("Replace")) {
      DoWrite(app, app->replace, app->replace_path, true);
      app->replace = Write::kNone;
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) {
      app->replace = Write::kNone;
      ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
  }
}

void RenderWindow(App* app) {
  RenderPanel& r = app->render;
  if (!r.open) return;
  ImGui::SetNextWindowPos(ImVec2(app->panel_width + 10.0f, 10.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(420.0f, 420.0f), ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Render", &r.open)) {
    ImGui::End();
    return;
  }
  ImGui::SliderInt("width (px)", &r.width, 64, 1280);
  ImGui::SliderInt("samples/pixel", &r.spp, 1, 256);
  if (ImGui::Button(r.running ? "Restart" : "Render")) StartRender(app);
  ImGui::SameLine();
  if (ImGui::Button("Cancel") && r.running) r.Stop();
  const long done = r.tiles_done.load(), total = r.tiles_total.load();
  char label[96];
  std::snprintf(label, sizeof(label), "%d spp shown%s", r.shown_samples,
                r.running ? "" : (r.shown_samples > 0 ? ", done" : ""));
  ImGui::ProgressBar(total > 0 ? static_cast<float>(done) / total : 0.0f, ImVec2(-1, 0), label);
  {
    std::lock_guard<std::mutex> lock(r.mutex);
    if (!r.error.empty()) ImGui::TextWrapped("%s", r.error.c_str());
    if (!r.running && r.seconds > 0.0) ImGui::Text("rendered in %.1f s", r.seconds);
  }
  if (r.texture && r.shown.width > 0) {
    const float w = std::max(32.0f, ImGui::GetContentRegionAvail().x);
    const float h = w * r.shown.height / r.shown.width;
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(r.texture)),
                 ImVec2(w, h));
  }
  ImGui::InputText("##png", r.png_path, sizeof(r.png_path));
  ImGui::SameLine();
  if (ImGui::Button("Save PNG")) TryWrite(app, Write::kPng, r.png_path);
  ImGui::End();
}

// ---------------------------------------------------------------------------------------------
// The panel

// Records the last item's rectangle (window coordinates) under a name, for --report.
void Record(App* app, const std::string& name) {
  if (app->report_path.empty()) return;
  const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
  app->widgets[name] = {a.x, a.y, b.x, b.y};
}

// A slider of a numeric field that edits the document when released: while it is active it
// shows its own value (FieldEdit), and the release commits that value, as a double (a value
// typed after Ctrl+click is stored as typed: "0.2" is 0.2, not the float 0.200000003).
void FieldSlider(App* app, const char* label, const std::string& field, double min, double max,
                 double fallback, const char* format = "%.3f") {
  const ImGuiID id = ImGui::GetID(label);
  const nlohmann::ordered_json v = app->session.Parameter(field);
  double value = v.is_number() ? v.get<double>() : fallback;
  if (app->edit.id == id) value = app->edit.value[0];
  ImGui::SetNextItemWidth(FieldWidth());
  ImGui::SliderScalar(label, ImGuiDataType_Double, &value, &min, &max, format);
  Record(app, field);
  if (ImGui::IsItemActive()) {
    app->edit.id = id;
    app->edit.value[0] = value;
  }
  if (ImGui::IsItemDeactivatedAfterEdit()) SetField(app, field, value);
  if (ImGui::IsItemDeactivated() && app->edit.id == id) app->edit.id = 0;
}

void FieldInt(App* app, const char* label, const std::string& field, int min, int max,
              int fallback) {
  const ImGuiID id = ImGui::GetID(label);
  const nlohmann::ordered_json v = app->session.Parameter(field);
  int value = v.is_number() ? v.get<int>() : fallback;
  if (app->edit.id == id) value = app->edit.int_value;
  ImGui::SetNextItemWidth(FieldWidth());
  ImGui::SliderInt(label, &value, min, max);
  Record(app, field);
  if (ImGui::IsItemActive()) {
    app->edit.id = id;
    app->edit.int_value = value;
  }
  if (ImGui::IsItemDeactivatedAfterEdit()) SetField(app, field, value);
  if (ImGui::IsItemDeactivated() && app->edit.id == id) app->edit.id = 0;
}

void FieldCheckbox(App* app, const char* label, const std::string& field, bool fallback) {
  const nlohmann::ordered_json v = app->session.Parameter(field);
  bool value = v.is_boolean() ? v.get<bool>() : fallback;
  const bool clicked = ImGui::Checkbox(label, &value);
  Record(app, field);
  if (clicked) SetField(app, field, value);
}

// A 3-vector field (e.g. comb.direction), edited component by component (the group's own
// value while active, as FieldSlider).
void FieldVector3(App* app, const char* label, const std::string& field, double min, double max,
                  const double fallback[3]) {
  const ImGuiID id = ImGui::GetID(label);
  const nlohmann::ordered_json v = app->session.Parameter(field);
  double value[3] = {fallback[0], fallback[1], fallback[2]};
  if (v.is_array() && v.size() == 3) {
    for (int k = 0; k < 3; ++k) {
      if (v[k].is_number()) value[k] = v[k].get<double>();
    }
  }
  if (app->edit.id == id) std::copy(app->edit.value, app->edit.value + 3, value);
  ImGui::SetNextItemWidth(FieldWidth());
  ImGui::SliderScalarN(label, ImGuiDataType_Double, value, 3, &min, &max, "%.2f");
  Record(app, field);
  if (ImGui::IsItemActive()) {
    app->edit.id = id;
    std::copy(value, value + 3, app->edit.value);
  }
  if (ImGui::IsItemDeactivatedAfterEdit()) {
    SetField(app, field, nlohmann::ordered_json::array({value[0], value[1], value[2]}));
  }
  if (ImGui::IsItemDeactivated() && app->edit.id == id) app->edit.id = 0;
}

void FieldCombo(App* app, const char* label, const std::string& field,
                const std::vector<const char*>& items, const char* fallback) {
  const nlohmann::ordered_json v = app->session.Parameter(field);
  const std::string current = v.is_string() ? v.get<std::string>() : fallback;
  if (ImGui::BeginCombo(label, current.c_str())) {
    for (const char* item : items) {
      if (ImGui::Selectable(item, current == item) && current != item) {
        SetField(app, field, item);
      }
    }
    ImGui::EndCombo();
  }
}

// A button whose rectangle --report records under `name`.
bool Button(App* app, const char* label, const std::string& name) {
  const bool clicked = ImGui::Button(label);
  Record(app, name);
  return clicked;
}

// A slider of the panel's own state (not the document), of the fields' width (narrower when a
// button follows on its row).
bool Slider(App* app, const char* label, float* value, float min, float max,
            const char* format = "%.3f", float width = 0.0f) {
  ImGui::SetNextItemWidth(width > 0.0f ? width : FieldWidth());
  const bool changed = ImGui::SliderFloat(label, value, min, max, format);
  Record(app, label);
  return changed;
}

// Ends a block of rows that is always `rows` rows high, so that what follows does not move when
// the block shows fewer (the cut tool's rows, the status lines): clicks land where they aimed.
void PadRows(float top, int rows) {
  const float used = ImGui::GetCursorPosY() - top;
  const float height = rows * ImGui::GetFrameHeightWithSpacing();
  if (used < height) ImGui::Dummy(ImVec2(1.0f, height - used - ImGui::GetStyle().ItemSpacing.y));
}

void Panel(App* app) {
  int w, h;
  WindowSize(app, &w, &h);
  // Resizable by its right edge (ImGui's window border), the height the window's.
  const float em = ImGui::GetFontSize();
  if (app->panel_width <= 0.0f) app->panel_width = kPanelEm * em;
  const float max_width = std::max(kMinPanelEm * em, static_cast<float>(w) - kMinViewPixels);
  app->panel_width = std::clamp(app->panel_width, kMinPanelEm * em, max_width);
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(app->panel_width, static_cast<float>(h)));
  ImGui::SetNextWindowSizeConstraints(ImVec2(kMinPanelEm * em, static_cast<float>(h)),
                                      ImVec2(max_width, static_cast<float>(h)));
  ImGui::Begin("ringlet studio", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse);
  app->panel_width = ImGui::GetWindowWidth();
  // --report: the widest row of the last frame (labels and text included) and the width rows
  // have (the window less its padding and vertical scrollbar).
  app->panel_content_width = ImGui::GetCurrentWindow()->ContentSize.x;
  app->panel_inner_width = ImGui::GetCurrentWindow()->WorkRect.GetWidth();
  app->widgets = nlohmann::ordered_json::object();  // --report: the widgets of this frame
  Session& s = app->session;
  // Files.
  ImGui::SetNextItemWidth(-3.0f * em);
  ImGui::InputText("file", app->path, sizeof(app->path));
  Record(app, "file");
  if (Button(app, "Open", "Open")) Guard(app, Guarded::kOpen, app->path);
  ImGui::SameLine();
  if (Button(app, "New", "New")) Guard(app, Guarded::kNew);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(FieldWidth() - 2.0f * em);
  ImGui::InputText("##save", app->save_path, sizeof(app->save_path));
  Record(app, "save_path");
  ImGui::SameLine();
  if (Button(app, "Save", "Save")) {
    // The document's own file is replaced; any other existing file is asked about.
    if (app->save_path == s.Path()) {
      DoWrite(app, Write::kSave, app->save_path, true);
    } else {
      TryWrite(app, Write::kSave, app->save_path);
    }
  }
  ImGui::SetNextItemWidth(FieldWidth() - 2.0f * em);
  ImGui::InputText("##export", app->export_path, sizeof(app->export_path));
  Record(app, "export_path");
  ImGui::SameLine();
  if (Button(app, "Export", "Export")) TryWrite(app, Write::kExport, app->export_path);
  ImGui::SameLine();
  ImGui::TextDisabled("(.hair .usda .obj)");
  if (Button(app, "Render...", "Render")) {
    app->render.open = true;
    if (!app->render.running) StartRender(app);
  }
  ImGui::SameLine();
  ImGui::BeginDisabled(!s.CanUndo());
  if (Button(app, "Undo", "Undo") && s.Undo()) Edited(app);
  ImGui::EndDisabled();
  ImGui::SameLine();
  ImGui::BeginDisabled(!s.CanRedo());
  if (Button(app, "Redo", "Redo") && s.Redo()) Edited(app);
  ImGui::EndDisabled();
  ImGui::SameLine();
  ImGui::Text("%s", s.Modified() ? "(unsaved changes)" : "");

  // Solve status: always the same rows (the result lines and two of message), so that the
  // controls below never move.
  ImGui::Separator();
  int done = 0, total = 0;
  std::string what;
  s.Progress(&done, &total, &what);
  if (s.Busy()) {
    ImGui::ProgressBar(total > 0 ? static_cast<float>(done) / total : 0.0f, ImVec2(-1, 0),
                       what.c_str());
  } else {
    ImGui::ProgressBar(1.0f, ImVec2(-1, 0), s.Hair() ? "solved" : "no hairstyle");
  }
  if (const auto hair = s.Hair()) {
    const SolveStats& st = hair->stats;
    // A file with operations solves a master once per step (groom, then each operation).
    ImGui::Text("%s: %d master solves, %d masters (%d kept)", st.what.c_str(), st.resolved,
                st.masters, st.reused);
    ImGui::Text("%ld iterations, %.0f ms (edit to screen %.0f ms)", st.iterations, st.seconds * 1e3,
                app->last_latency * 1e3);
    ImGui::TextColored(
        st.unconverged + st.unstable > 0 ? ImVec4(1, 0.3f, 0.2f, 1) : ImVec4(0.6f, 1, 0.6f, 1),
        "%d unconverged, %d unstable, max penetration %.2f mm", st.unconverged, st.unstable,
        st.max_penetration * 1e3);
    ImGui::Text("%d strands, %ld segments drawn", hair->strands ? hair->strands->NumStrands() : 0,
                app->viewer.DrawnSegments());
  } else {
    for (int k = 0; k < 4; ++k) ImGui::TextDisabled("-");
  }
  // The last message: two lines, scrolled when longer.
  ImGui::BeginChild("message", ImVec2(0, 2.0f * ImGui::GetTextLineHeightWithSpacing()), false);
  ImGui::TextWrapped("%s", app->message.c_str());
  ImGui::EndChild();

  // The hairstyle, in groomers' words.
  ImGui::Separator();
  // Explicit masters (a masters file, e.g. from `ringlet invert`): the controls that would
  // sample them again are disabled (the parser refuses those keys with masters.file).
  const nlohmann::ordered_json masters_file = s.Parameter("masters.file");
  const bool explicit_masters = !masters_file.is_null();
  if (explicit_masters) {
    ImGui::TextWrapped("masters from %s: length, master count, root seed and comb come from "
                       "that file (disabled)", masters_file.dump().c_str());
  }
  if (ImGui::CollapsingHeader("Hair", ImGuiTreeNodeFlags_DefaultOpen)) {
    FieldCombo(app, "origin", "hair.origin", {"asian", "caucasian", "african"}, "caucasian");
    FieldCombo(app, "curl type", "hair.curl", {"straight", "wavy", "curly", "kinky"}, "wavy");
    ImGui::BeginDisabled(explicit_masters);
    // One slider per region of a regional length (front / side / back): one number would
    // replace them all.
    for (const std::string& field : LengthFields(s.CurrentDocument().parameters)) {
      const std::string label =
          field == "hair.length" ? "length (m)" : "length, " + field.substr(12) + " (m)";
      FieldSlider(app, label.c_str(), field, 0.05, 0.8, 0.25);
    }
    ImGui::EndDisabled();
    FieldInt(app, "hair seed", "hair.seed", 0, 100, 1);
    // The section and the natural curl in the groomer's terms (hair.ellipticity,
    // hair.curl_radius, hair.curl_pitch, hair.curl_spread), shown at the hair type's values
    // until set.
    if (const auto hair = s.Hair()) {
      const HairType& type = hair->styled.style.hair_type;
      FieldSlider(app, "a/b", "hair.ellipticity", 1.0, 3.0, type.ellipticity);
      ImGui::BeginDisabled(type.IsStraight());  // no helix to size (the reader refuses it)
      FieldSlider(app, "natural R (m)", "hair.curl_radius", 0.0005, 0.1,
                  type.IsStraight() ? 0.0 : type.curl_radius, "%.4f");
      FieldSlider(app, "natural pitch (m)", "hair.curl_pitch", 0.0, 0.2,
                  type.IsStraight() ? 0.0 : type.curl_pitch, "%.4f");
      FieldSlider(app, "curl spread", "hair.curl_spread", 0.0, 1.0,
                  type.IsStraight() ? 0.0 : type.curl_radius_std / type.curl_radius);
      ImGui::EndDisabled();
    }
  }
  if (ImGui::CollapsingHeader("Masters and wisps")) {
    Record(app, "header.masters");
    ImGui::BeginDisabled(explicit_masters);
    FieldInt(app, "masters", "masters.count", 10, 3000, 1000);
    FieldInt(app, "root seed", "masters.seed", 0, 100, 0);
    ImGui::EndDisabled();
    FieldInt(app, "strands/wisp", "wisps.strands_per_wisp", 1, 200, 100);
    // Wisp size: "auto" (from each master's curliness) until set; the button restores it.
    if (const auto hair = s.Hair(); hair && !hair->styled.masters.wisp_radii.empty()) {
      const std::vector<double>& radii = hair->styled.masters.wisp_radii;
      double mean = 0.0;
      for (const double r : radii) mean += r / static_cast<double>(radii.size());
      FieldSlider(app, "wisp radius (m)", "wisps.radius", 0.0005, 0.02, mean, "%.4f");
      ImGui::SameLine();
      if (ImGui::SmallButton("auto")) SetField(app, "wisps.radius", "auto");
      Record(app, "wisps.radius.auto");
    }
    FieldSlider(app, "tip scale", "wisps.tip_scale", 0.0, 2.0, 0.5);
    FieldSlider(app, "jitter (m)", "wisps.jitter", 0.0, 0.01, 0.0, "%.4f");
    FieldSlider(app, "length var.", "wisps.length_variation", 0.0, 0.5, 0.1);
    FieldInt(app, "hull layers", "layers.count", 1, 10, 4);
    FieldSlider(app, "layer gap (m)", "layers.thickness", 0.0, 0.01, 0.004, "%.4f");
  } else {
    Record(app, "header.masters");
  }
  if (ImGui::CollapsingHeader("Comb")) {
    Record(app, "header.comb");
    ImGui::BeginDisabled(explicit_masters);
    const double down[3] = {0.0, 0.0, -1.0};
    FieldVector3(app, "direction", "comb.direction", -1.0, 1.0, down);
    FieldSlider(app, "tilt (rad)", "comb.tilt", 0.0, 1.5707, 1.2);
    FieldSlider(app, "face sweep", "comb.face_sweep", 0.0, 2.0, 0.0);
    FieldSlider(app, "parting offset", "comb.parting.offset", -0.08, 0.08, 0.0);
    FieldCheckbox(app, "waves laid into the head", "comb.curl_inward", false);
    ImGui::EndDisabled();
  } else {
    Record(app, "header.comb");
  }

  // Operations.
  ImGui::Separator();
  ImGui::Text("Styling");
  if (ImGui::Checkbox("brush: paint roots (left drag; Ctrl erases)", &app->brush_mode) &&
      app->brush_mode) {
    app->sculpt_tool = 0;
  }
  Record(app, "brush");
  Slider(app, "brush radius (px)", &app->brush_radius, 5.0f, 150.0f, "%.0f");
  ImGui::Text("%zu masters brushed", s.brush.size());
  ImGui::SameLine();
  if (Button(app, "clear", "brush.clear")) {
    s.brush.clear();
    app->viewer.SetBrush(s.brush);
  }
  ImGui::Checkbox("operations act on the brushed masters only", &app->brush_only);
  Record(app, "brush_only");
  // The sculpting brushes: one tool at a time with the root brush and the cut tool.
  ImGui::Text("sculpt (left drag in the view):");
  const int sculpt_before = app->sculpt_tool;
  ImGui::RadioButton("off##sculpt", &app->sculpt_tool, 0);
  Record(app, "sculpt.off");
  ImGui::SameLine();
  ImGui::RadioButton("comb", &app->sculpt_tool, 1);
  Record(app, "sculpt.comb");
  ImGui::SameLine();
  ImGui::RadioButton("puff (Shift: flatten)", &app->sculpt_tool, 2);
  Record(app, "sculpt.puff");
  ImGui::SameLine();
  ImGui::RadioButton("parting", &app->sculpt_tool, 3);
  Record(app, "sculpt.parting");
  ImGui::RadioButton("length", &app->sculpt_tool, 4);
  Record(app, "sculpt.length");
  ImGui::SameLine();
  ImGui::RadioButton("clump", &app->sculpt_tool, 5);
  Record(app, "sculpt.clump");
  ImGui::SameLine();
  ImGui::RadioButton("frizz", &app->sculpt_tool, 6);
  Record(app, "sculpt.frizz");
  ImGui::SameLine();
  ImGui::RadioButton("curl", &app->sculpt_tool, 7);
  Record(app, "sculpt.curl");
  ImGui::SameLine();
  ImGui::TextDisabled("(Shift: invert)");
  if (app->sculpt_tool != sculpt_before && app->sculpt_tool != 0) {
    app->brush_mode = false;
    app->cut_tool = 0;
  }
  Slider(app, "sculpt radius (mm)", &app->sculpt_radius_mm, 5.0f, 150.0f, "%.0f");
  Slider(app, "strength", &app->sculpt_strength, 0.05f, 1.0f, "%.2f");
  Slider(app, "puff angle (deg)", &app->puff_degrees, 1.0f, 60.0f, "%.0f");
  Slider(app, "length factor", &app->length_factor, 0.3f, 0.99f, "%.2f");
  Slider(app, "clump factor", &app->clump_factor, 0.1f, 0.99f, "%.2f");
  Slider(app, "frizz (mm)", &app->frizz_mm, 0.1f, 20.0f, "%.1f");
  ImGui::SetNextItemWidth(FieldWidth());
  ImGui::Combo("falloff", &app->sculpt_falloff, "smooth\0linear\0constant\0");
  Record(app, "falloff");
  ImGui::Checkbox("mirror (both sides of the head)", &app->sculpt_mirror);
  Record(app, "mirror");
  Slider(app, "curl radius (mm)", &app->curl_radius_mm, 1.0f, 50.0f, "%.1f");
  Slider(app, "curl pitch (mm)", &app->curl_pitch_mm, -60.0f, 60.0f, "%.1f");
  if (Button(app, "Curl", "Curl")) {
    AddOperation(app, Curl(app, app->curl_radius_mm * 1e-3, app->curl_pitch_mm * 1e-3));
  }
  ImGui::SameLine();
  if (Button(app, "Straighten", "Straighten")) {
    AddOperation(app, Curl(app, std::numeric_limits<double>::infinity(), 0.0));
  }
  ImGui::SameLine();
  if (Button(app, "Wet", "Wet")) {
    AddOperation(app, Brushed(app, Simple(StyleOperation::Kind::kWet)));
  }
  ImGui::SameLine();
  if (Button(app, "Dry", "Dry")) {
    AddOperation(app, Brushed(app, Simple(StyleOperation::Kind::kDry)));
  }
  ImGui::Text("cut tool (drag in the view; Shift tilts):");
  ImGui::RadioButton("off", &app->cut_tool, 0);
  Record(app, "cut_tool.off");
  ImGui::SameLine();
  if (ImGui::RadioButton("plane", &app->cut_tool, 1)) app->sculpt_tool = 0;
  Record(app, "cut_tool.plane");
  ImGui::SameLine();
  if (ImGui::RadioButton("sphere", &app->cut_tool, 2)) app->sculpt_tool = 0;
  Record(app, "cut_tool.sphere");
  ImGui::SameLine();
  ImGui::BeginDisabled(app->cut_tool == 0);
  if (Button(app, "Apply cut (Enter)", "Apply cut")) {
    StyleOperation op = Simple(StyleOperation::Kind::kCut);
    op.cut_region = GizmoRegion(app);
    AddOperation(app, Brushed(app, op));
  }
  ImGui::EndDisabled();
  // The tool's rows: always three (plane, or off: height, tilt, roll, disabled when off;
  // sphere: centre, radius).
  const float tool_top = ImGui::GetCursorPosY();
  if (app->cut_tool != 2) {
    ImGui::BeginDisabled(app->cut_tool == 0);
    Slider(app, "plane height (m)", &app->plane_height, -0.5f, 0.2f);
    Slider(app, "tilt (deg)", &app->plane_tilt, -80.0f, 80.0f, "%.1f");
    Slider(app, "roll (deg)", &app->plane_roll, -80.0f, 80.0f, "%.1f");
    ImGui::EndDisabled();
  } else {
    ImGui::SetNextItemWidth(FieldWidth());
    ImGui::SliderFloat3("centre (m)", app->sphere_centre, -0.3f, 0.3f);
    Record(app, "centre (m)");
    Slider(app, "radius (m)", &app->sphere_radius, 0.02f, 0.6f);
  }
  PadRows(tool_top, 3);
  Slider(app, "cut height (m)", &app->cut_z, -0.4f, 0.1f, "%.3f",
         FieldWidth() - 2.0f * ImGui::GetFontSize());
  ImGui::SameLine();
  if (Button(app, "Cut below", "Cut below")) AddOperation(app, Brushed(app, CutZ(app->cut_z)));
  Slider(app, "max length (m)", &app->cut_length, 0.02f, 0.8f, "%.3f",
         FieldWidth() - 2.0f * ImGui::GetFontSize());
  ImGui::SameLine();
  if (Button(app, "Cut to length", "Cut to length")) {
    StyleOperation op = Simple(StyleOperation::Kind::kCut);
    op.cut_region.kind = CutRegion::Kind::kMaxLength;
    op.cut_region.length = app->cut_length;
    AddOperation(app, Brushed(app, op));
  }
  Slider(app, "grow step (mm)", &app->grow_step_mm, 1.0f, 50.0f, "%.1f");
  ImGui::SetNextItemWidth(FieldWidth() - 2.0f * ImGui::GetFontSize());
  ImGui::SliderInt("grow steps", &app->grow_steps, 1, 10);
  Record(app, "grow steps");
  ImGui::SameLine();
  if (Button(app, "Grow", "Grow")) {
    StyleOperation op = Simple(StyleOperation::Kind::kGrow);
    op.grow_step = app->grow_step_mm * 1e-3;
    op.grow_steps = app->grow_steps;
    AddOperation(app, Brushed(app, op));
  }

  // View.
  ImGui::Separator();
  ImGui::Checkbox("masters only (M)", &app->look.masters_only);
  Record(app, "masters_only");
  ImGui::SameLine();
  ImGui::Checkbox("highlight masters", &app->look.highlight_masters);
  ImGui::Checkbox("headlight (the light follows the camera)", &app->look.headlight);
  Record(app, "headlight");
  ImGui::TextWrapped(
      "Mouse: left drag orbits (Alt+left or middle drag orbits also while the brush or the cut "
      "tool is on), right drag pans, wheel zooms. Views: 1 front, 3 right side, 7 top; with "
      "Ctrl the opposite (back, left side, bottom); F frames all, arrows orbit, +/- zoom. "
      "M masters only, Ctrl+Z undo, Ctrl+Y redo, Enter applies the cut tool's cut. "
      "Red: unconverged, magenta: unstable, cyan: brushed.");
  if (ImGui::CollapsingHeader("History")) {
    const std::vector<std::string> labels = s.HistoryLabels();
    for (int k = 0; k < static_cast<int>(labels.size()); ++k) {
      ImGui::Text("%s %s", k == s.HistoryCursor() ? ">" : " ", labels[k].c_str());
    }
  }
  ImGui::End();
}

// ---------------------------------------------------------------------------------------------
// Input

App* AppOf(GLFWwindow* window) { return static_cast<App*>(glfwGetWindowUserPointer(window)); }

void Queue(GLFWwindow* window, const InputEvent& event) {
  AppOf(window)->events.push_back(event);
}

// GLFW's callbacks: every event is queued in order; ImGui's backend polls nothing of ours (it is
// initialised without callbacks) and is given the state of the events each frame takes.
void InstallCallbacks(GLFWwindow* window) {
  glfwSetCursorPosCallback(window, [](GLFWwindow* w, double x, double y) {
    InputEvent e;
    e.kind = InputEvent::Kind::kMove;
    e.x = x;
    e.y = y;
    Queue(w, e);
  });
  glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int mods) {
    InputEvent e;
    e.kind = InputEvent::Kind::kButton;
    e.code = button;
    e.action = action;
    e.mods = mods;
    Queue(w, e);  // at the cursor of the last move before it (set when taken)
  });
  glfwSetScrollCallback(window, [](GLFWwindow* w, double dx, double dy) {
    InputEvent e;
    e.kind = InputEvent::Kind::kScroll;
    e.x = dx;
    e.y = dy;
    Queue(w, e);
  });
  glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int mods) {
    InputEvent e;
    e.kind = InputEvent::Kind::kKey;
    e.code = key;
    e.action = action;
    e.mods = mods;
    Queue(w, e);
  });
  glfwSetCharCallback(window, [](GLFWwindow* w, unsigned c) {
    InputEvent e;
    e.kind = InputEvent::Kind::kChar;
    e.code = static_cast<int>(c);
    Queue(w, e);
  });
  glfwSetWindowFocusCallback(window, [](GLFWwindow* w, int focused) {
    ImGui_ImplGlfw_WindowFocusCallback(w, focused);
    AppOf(w)->redraw_frames = std::max(AppOf(w)->redraw_frames, 2);
  });
  glfwSetCursorEnterCallback(window, [](GLFWwindow* w, int entered) {
    ImGui_ImplGlfw_CursorEnterCallback(w, entered);
  });
  glfwSetWindowRefreshCallback(window, [](GLFWwindow* w) {
    AppOf(w)->redraw_frames = std::max(AppOf(w)->redraw_frames, 1);
  });
  glfwSetFramebufferSizeCallback(window, [](GLFWwindow* w, int, int) {
    AppOf(w)->redraw_frames = std::max(AppOf(w)->redraw_frames, 2);
  });
}

// Takes the events of one frame from the queue, in order, and updates the state given to ImGui
// (cursor, buttons, keys). ImGui sees one state per frame, so the run stops (as ImGui 1.87's
// input queue "trickles" fast input) before a second change of a button or key already changed
// in this frame, a move after a button change, a release after a move (a slider must see where
// it was dragged before it is released), a key release after a key press (a shortcut's keys are
// seen down together), and typed characters after a change of a key ImGui reads (Enter,
// Backspace, ...). A click or key tap shorter than a frame is thus spread over
// two frames instead of lost, and a press is seen at its own cursor position.
std::vector<InputEvent> TakeFrameEvents(App* app) {
  const ImGuiIO& io = ImGui::GetIO();
  const auto mapped = [&io](int key) {
    return std::find(std::begin(io.KeyMap), std::end(io.KeyMap), key) != std::end(io.KeyMap);
  };
  std::vector<InputEvent> taken;
  std::vector<int> changed_keys;
  int changed_buttons = 0;  // bit per button
  bool moved = false, mapped_changed = false, key_pressed = false;
  size_t k = 0;
  for (; k < app->events.size(); ++k) {
    InputEvent& e = app->events[k];
    bool stop = false;
    switch (e.kind) {
      case InputEvent::Kind::kMove:
      case InputEvent::Kind::kScroll:
        stop = changed_buttons != 0;
        break;
      case InputEvent::Kind::kButton:
        stop = (e.code >= 0 && e.code < 5 && (changed_buttons & (1 << e.code))) ||
               (e.action == GLFW_RELEASE && moved);
        break;
      case InputEvent::Kind::kKey:
        // Also a release after a press of another key: Ctrl+A sent as Ctrl down, A down, Ctrl
        // up, A up must be seen with both keys down in one frame.
        stop = e.action != GLFW_REPEAT &&
               (std::find(changed_keys.begin(), changed_keys.end(), e.code) != changed_keys.end() ||
                (e.action == GLFW_RELEASE && key_pressed));
        break;
      case InputEvent::Kind::kChar:
        stop = mapped_changed;
        break;
    }
    if (stop) break;
    switch (e.kind) {
      case InputEvent::Kind::kMove:
        app->cursor_x = e.x;
        app->cursor_y = e.y;
        moved = true;
        break;
      case InputEvent::Kind::kButton:
        e.x = app->cursor_x;
        e.y = app->cursor_y;
        if (e.code >= 0 && e.code < 5) {
          app->mouse_down[e.code] = e.action == GLFW_PRESS;
          changed_buttons |= 1 << e.code;
        }
        break;
      case InputEvent::Kind::kKey:
        if (e.action == GLFW_REPEAT) break;
        if (e.code >= 0 && e.code < 512) app->keys_down[e.code] = e.action == GLFW_PRESS;
        changed_keys.push_back(e.code);
        key_pressed = key_pressed || e.action == GLFW_PRESS;
        mapped_changed = mapped_changed || mapped(e.code);
        break;
      case InputEvent::Kind::kChar:
      case InputEvent::Kind::kScroll:
        break;
    }
    taken.push_back(e);
  }
  app->events.erase(app->events.begin(), app->events.begin() + static_cast<long>(k));
  return taken;
}

// Gives ImGui the state after this frame's events (after ImGui_ImplGlfw_NewFrame, which would
// poll the current state instead).
void FeedImGui(App* app, const std::vector<InputEvent>& events) {
  ImGuiIO& io = ImGui::GetIO();
  io.MousePos = ImVec2(static_cast<float>(app->cursor_x), static_cast<float>(app->cursor_y));
  for (int b = 0; b < 5; ++b) io.MouseDown[b] = app->mouse_down[b];
  for (int k = 0; k < 512; ++k) io.KeysDown[k] = app->keys_down[k];
  const bool* d = app->keys_down;
  io.KeyCtrl = d[GLFW_KEY_LEFT_CONTROL] || d[GLFW_KEY_RIGHT_CONTROL];
  io.KeyShift = d[GLFW_KEY_LEFT_SHIFT] || d[GLFW_KEY_RIGHT_SHIFT];
  io.KeyAlt = d[GLFW_KEY_LEFT_ALT] || d[GLFW_KEY_RIGHT_ALT];
  io.KeySuper = d[GLFW_KEY_LEFT_SUPER] || d[GLFW_KEY_RIGHT_SUPER];
  for (const InputEvent& e : events) {
    if (e.kind == InputEvent::Kind::kScroll) {
      io.MouseWheelH += static_cast<float>(e.x);
      io.MouseWheel += static_cast<float>(e.y);
    } else if (e.kind == InputEvent::Kind::kChar) {
      io.AddInputCharacter(static_cast<unsigned>(e.code));
    }
  }
}

// Framebuffer pixels per window coordinate.
float PixelScale(App* app) {
  int ww, wh, fw, fh;
  WindowSize(app, &ww, &wh);
  FramebufferSize(app, &fw, &fh);
  return ww > 0 ? static_cast<float>(fw) / ww : 1.0f;
}

// ---------------------------------------------------------------------------------------------
// The sculpting brushes (brush_tool.h): the mouse becomes sculpt and puff operations.

// The ray from the eye through the window point (x, y) (window coordinates) of the 3D view,
// by inverting the view's projection (the columns right of the panel, as Viewer::Draw).
Ray ViewRay(App* app, double x, double y) {
  int fw, fh;
  FramebufferSize(app, &fw, &fh);
  const float scale = PixelScale(app);
  const int x0 = PanelPixels(app);
  const int width = std::max(1, fw - x0), height = std::max(1, fh);
  const Eigen::Matrix4f vp =
      app->camera.Projection(static_cast<float>(width) / height) * app->camera.View();
  const Eigen::Matrix4f inverse = vp.inverse();
  const float nx = 2.0f * (static_cast<float>(x) * scale - x0) / width - 1.0f;
  const float ny = 1.0f - 2.0f * static_cast<float>(y) * scale / height;
  const Eigen::Vector4f a = inverse * Eigen::Vector4f(nx, ny, -1.0f, 1.0f);
  const Eigen::Vector4f b = inverse * Eigen::Vector4f(nx, ny, 1.0f, 1.0f);
  const Vec3 near = (a.head<3>() / a.w()).cast<double>(), far = (b.head<3>() / b.w()).cast<double>();
  return Ray{app->camera.Position().cast<double>(), (far - near).normalized()};
}

// The window point (window coordinates) where the world point p is drawn, if in front.
std::optional<ImVec2> ViewPoint(App* app, const Vec3& p) {
  int fw, fh;
  FramebufferSize(app, &fw, &fh);
  const float scale = PixelScale(app);
  const int x0 = PanelPixels(app);
  const int width = std::max(1, fw - x0), height = std::max(1, fh);
  const Eigen::Vector4f clip =
      app->camera.Projection(static_cast<float>(width) / height) * app->camera.View() *
      Eigen::Vector4f(static_cast<float>(p.x()), static_cast<float>(p.y()),
                      static_cast<float>(p.z()), 1.0f);
  if (clip.w() <= 0.0f) return std::nullopt;
  const float sx = (clip.x() / clip.w() * 0.5f + 0.5f) * width + x0;
  const float sy = (0.5f - clip.y() / clip.w() * 0.5f) * height;
  return ImVec2(sx / scale, sy / scale);
}

// A panel value as the user reads it (6 decimals: 0.8f is 0.8, not 0.800000011920929).
double Typed(float value) { return std::stod(std::to_string(value)); }

BrushSettings SculptBrush(const App* app) {
  BrushSettings b;
  b.radius = app->sculpt_radius_mm * 1e-3;
  b.strength = app->sculpt_strength;
  b.falloff = static_cast<Brush::Falloff>(app->sculpt_falloff);
  b.mirror = app->sculpt_mirror;
  b.puff_angle = app->puff_degrees * std::numbers::pi / 180.0;
  // The panel's float values as the user reads them (%.2f: 0.8 is 0.8, not 0.800000011920929).
  b.length_factor = Typed(app->length_factor);
  b.clump_factor = Typed(app->clump_factor);
  b.frizz_amplitude = Typed(app->frizz_mm) * 1e-3;
  return b;
}

// A press of the left button with a sculpting tool on: the comb picks the hair under the brush
// (the point nearest the eye within the brush radius of the ray); the puff applies at once
// where the ray enters the head.
void SculptPress(App* app, double x, double y, int mods) {
  const auto hair = app->session.Hair();
  if (!hair) return;
  const Ray ray = ViewRay(app, x, y);
  const BrushSettings brush = SculptBrush(app);
  if (app->sculpt_tool == 1) {
    app->stroke_from = PickMasterPoint(hair->styled, ray, brush.radius);
    if (!app->stroke_from) {
      Report(app, "comb: no hair under the brush (press on the hair)");
      return;
    }
    app->stroke_view = (app->camera.target - app->camera.Position()).normalized().cast<double>();
    app->stroke_anchor = StrokeEnd(*app->stroke_from, ray, app->stroke_view);
    app->stroke_to = *app->stroke_from;
    return;
  }
  if (app->sculpt_tool >= 4) {
    const std::optional<Vec3> centre = PickBrushCentre(hair->styled, ray, brush.radius, 100.0);
    const char* name = app->sculpt_tool == 4   ? "length"
                       : app->sculpt_tool == 5 ? "clump"
                       : app->sculpt_tool == 6 ? "frizz"
                                               : "curl";
    if (!centre) {
      Report(app, std::string(name) + ": no hair or head under the brush (click on the hair)");
      return;
    }
    const bool invert = (mods & GLFW_MOD_SHIFT) != 0;
    // The curl tool curls toward the panel's curl radius and pitch (Shift straightens).
    AddOperation(app, app->sculpt_tool == 4   ? LengthOperation(brush, *centre, invert)
                      : app->sculpt_tool == 5 ? ClumpOperation(brush, *centre, invert)
                      : app->sculpt_tool == 6 ? FrizzOperation(brush, *centre, invert)
                                              : CurlOperation(brush, *centre,
                                                              Typed(app->curl_radius_mm) * 1e-3,
                                                              Typed(app->curl_pitch_mm) * 1e-3,
                                                              invert));
    return;
  }
  const Body* body = hair->styled.style.body.get();
  const std::optional<Vec3> hit = body ? PickBodyPoint(*body, ray, 100.0) : std::nullopt;
  if (!hit) {
    Report(app, app->sculpt_tool == 3 ? "parting: press on the head"
                                      : "puff: no head under the cursor (click on the head)");
    return;
  }
  if (app->sculpt_tool == 3) {
    app->parting_from = *hit;
    app->parting_to = *hit;
    return;
  }
  AddOperation(app, PuffOperation(brush, *hit, (mods & GLFW_MOD_SHIFT) != 0));
}

// The parting plane of a line drawn on the head from a to b: the plane through both that
// contains the head's up axis, n = (b - a) x up / |(b - a) x up|, n . (p - c) = n . (a - c) (c the
// head centre): a parting from the forehead to the crown along a meridian or parallel to it
// (docs/hairstyle-format.md, comb.parting). None for a line along up or shorter than 5 mm.
std::optional<std::pair<Vec3, double>> PartingPlane(const HeadFrame& head, const Vec3& a,
                                                    const Vec3& b) {
  const Vec3 up = HeadAxes(head).col(0);
  const Vec3 n = (b - a).cross(up);
  if ((b - a).norm() < 5e-3 || !(n.norm() > 1e-3 * (b - a).norm())) return std::nullopt;
  const Vec3 unit = n.normalized();
  return std::pair{unit, unit.dot(a - head.centre)};
}

// The comb stroke follows the cursor in the view plane through its start (measured from the
// press, so the hair moves exactly as far as the mouse did at the hair's depth).
void SculptMove(App* app, double x, double y) {
  if (app->sculpt_tool == 3 && app->parting_from) {
    const auto hair = app->session.Hair();
    const Body* body = hair ? hair->styled.style.body.get() : nullptr;
    const std::optional<Vec3> hit =
        body ? PickBodyPoint(*body, ViewRay(app, x, y), 100.0) : std::nullopt;
    if (hit) app->parting_to = *hit;
    return;
  }
  if (app->sculpt_tool != 1 || !app->stroke_from) return;
  app->stroke_to = *app->stroke_from +
                   (StrokeEnd(*app->stroke_from, ViewRay(app, x, y), app->stroke_view) -
                    app->stroke_anchor);
}

// The release ends the stroke: one sculpt operation (none for a click without motion).
void SculptRelease(App* app, double x, double y) {
  SculptMove(app, x, y);
  if (app->sculpt_tool == 3 && app->parting_from) {
    const auto hair = app->session.Hair();
    const std::optional<std::pair<Vec3, double>> plane =
        hair ? PartingPlane(HairstyleHead(hair->styled.style), *app->parting_from,
                            app->parting_to)
             : std::nullopt;
    app->parting_from.reset();
    if (!plane) {
      Report(app, "parting: draw a line on the head (at least 5 mm, not straight up)");
      return;
    }
    // One edit of the document: the parting's plane, keeping its strength.
    const nlohmann::ordered_json& doc = app->session.CurrentDocument().parameters;
    nlohmann::ordered_json parting = {
        {"normal", {plane->first.x(), plane->first.y(), plane->first.z()}},
        {"offset", plane->second}};
    if (doc.contains("comb") && doc["comb"].is_object() && doc["comb"].contains("parting") &&
        doc["comb"]["parting"].is_object() && doc["comb"]["parting"].contains("strength")) {
      parting["strength"] = doc["comb"]["parting"]["strength"];
    }
    SetField(app, "comb.parting", parting);
    return;
  }
  if (app->sculpt_tool == 1 && app->stroke_from &&
      (app->stroke_to - *app->stroke_from).norm() > 1e-4) {
    AddOperation(app, SculptOperation(SculptBrush(app), *app->stroke_from, app->stroke_to));
  }
  app->stroke_from.reset();
}

// The brush circle at the cursor (its radius drawn at the depth of the view's target) and the
// comb stroke being dragged.
void DrawSculptOverlay(App* app) {
  if (app->sculpt_tool == 0) return;
  ImDrawList* draw = ImGui::GetForegroundDrawList();
  const ImU32 colour = IM_COL32(255, 220, 120, 220);
  if (app->sculpt_tool == 3) {
    // The document's parting on a sphere scalp: its plane's circle on the head above the
    // centre; and the line being drawn.
    const auto hair = app->session.Hair();
    if (hair && hair->styled.style.comb.parting) {
      if (const auto* sphere = std::get_if<SphereScalp>(&hair->styled.style.scalp)) {
        const CombOptions& comb = hair->styled.style.comb;
        const Vec3 n = comb.parting_normal.normalized(), c = sphere->head.centre;
        const Vec3 up = HeadAxes(sphere->head).col(0);
        const double r2 = sphere->radius * sphere->radius - comb.parting_offset * comb.parting_offset;
        if (r2 > 0.0) {
          const Vec3 u = n.cross(up).norm() > 1e-9 ? Vec3(n.cross(up).normalized()) : Vec3::UnitX();
          const Vec3 v = n.cross(u);
          std::vector<ImVec2> line;
          for (int k = 0; k <= 96; ++k) {
            const double t = 2.0 * std::numbers::pi * k / 96;
            const Vec3 p = c + comb.parting_offset * n +
                           std::sqrt(r2) * (std::cos(t) * u + std::sin(t) * v);
            const std::optional<ImVec2> q = (p - c).dot(up) > 0.0 ? ViewPoint(app, p) : std::nullopt;
            if (q) line.push_back(*q);
            if ((!q || k == 96) && line.size() > 1) {
              draw->AddPolyline(line.data(), static_cast<int>(line.size()),
                                IM_COL32(120, 200, 255, 200), 0, 2.0f);
            }
            if (!q) line.clear();
          }
        }
      }
    }
    if (app->parting_from) {
      const auto a = ViewPoint(app, *app->parting_from), b = ViewPoint(app, app->parting_to);
      if (a && b) draw->AddLine(*a, *b, colour, 2.0f);
    }
    return;
  }
  if (app->stroke_from) {
    const auto a = ViewPoint(app, *app->stroke_from), b = ViewPoint(app, app->stroke_to);
    if (a && b) {
      draw->AddLine(*a, *b, colour, 2.0f);
      draw->AddCircleFilled(*a, 3.0f, colour);
    }
  }
  const ImVec2 cursor(static_cast<float>(app->cursor_x), static_cast<float>(app->cursor_y));
  if (cursor.x < app->panel_width) return;
  int fw, fh;
  FramebufferSize(app, &fw, &fh);
  const float pixels = static_cast<float>(app->sculpt_radius_mm * 1e-3) /
                       (app->camera.distance * std::tan(0.5f * app->camera.fov)) * 0.5f *
                       static_cast<float>(fh) / PixelScale(app);
  draw->AddCircle(cursor, pixels, colour, 48, 1.5f);
  if (app->sculpt_mirror) {
    draw->AddText(ImVec2(cursor.x + pixels + 4.0f, cursor.y - ImGui::GetFontSize()), colour,
                  "mirror");
  }
}

// The drag in the view at cursor (x, y): the state at the press moved by the cursor's offset
// from the press.
void ApplyDrag(App* app, double x, double y) {
  ViewDrag& d = app->drag;
  const float scale = PixelScale(app);
  const float dx = static_cast<float>(x - d.x0), dy = static_cast<float>(y - d.y0);
  switch (d.mode) {
    case ViewDrag::Mode::kOrbit:
      app->camera = d.camera;
      app->camera.Orbit(-dx * 0.008f, dy * 0.008f);
      break;
    case ViewDrag::Mode::kPan: {
      // The scene follows the cursor: one pixel is the distance a pixel spans at the target.
      int fw, fh;
      FramebufferSize(app, &fw, &fh);
      const float k = 2.0f * std::tan(0.5f * d.camera.fov) / static_cast<float>(std::max(1, fh));
      app->camera = d.camera;
      app->camera.Pan(-dx * scale * k, dy * scale * k);
      break;
    }
    case ViewDrag::Mode::kBrush:
      Brush(app, static_cast<float>(x) * scale, static_cast<float>(y) * scale,
            (d.mods & GLFW_MOD_CONTROL) != 0);
      break;
    case ViewDrag::Mode::kSculpt:
      SculptMove(app, x, y);
      break;
    case ViewDrag::Mode::kGizmo:
      app->plane_height = d.plane_height;
      app->plane_tilt = d.plane_tilt;
      app->plane_roll = d.plane_roll;
      app->sphere_centre[2] = d.sphere_centre_z;
      app->sphere_radius = d.sphere_radius;
      DragGizmo(app, dx * scale, dy * scale, (d.mods & GLFW_MOD_SHIFT) != 0);
      break;
    case ViewDrag::Mode::kNone:
      break;
  }
}

// A shortcut key, once per press (never on key repeat), unless ImGui has the keyboard (a text
// field). The arrows and +/- (view steps) also step on key repeat while held.
void Shortcut(App* app, const InputEvent& e) {
  const bool press = e.action == GLFW_PRESS, repeat = e.action == GLFW_REPEAT;
  const bool ctrl = (e.mods & GLFW_MOD_CONTROL) != 0;
  Session& s = app->session;
  switch (e.code) {
    case GLFW_KEY_F:
      if (press && !ctrl) app->camera.Frame(app->viewer.Bounds());
      break;
    case GLFW_KEY_M:
      if (press && !ctrl) app->look.masters_only = !app->look.masters_only;
      break;
    case GLFW_KEY_F12:
      if (press) app->screenshot_key = true;
      break;
    // The view keys (numpad-like, the digits of the top row or of the keypad): 1 front, 3 the
    // head's right side, 7 top; with Ctrl the opposite view (back, left side, bottom).
    case GLFW_KEY_1:
    case GLFW_KEY_KP_1:
      if (press) app->camera.SetView(ctrl ? ViewSide::kBack : ViewSide::kFront);
      break;
    case GLFW_KEY_3:
    case GLFW_KEY_KP_3:
      if (press) app->camera.SetView(ctrl ? ViewSide::kLeft : ViewSide::kRight);
      break;
    case GLFW_KEY_7:
    case GLFW_KEY_KP_7:
      if (press) app->camera.SetView(ctrl ? ViewSide::kBottom : ViewSide::kTop);
      break;
    case GLFW_KEY_Z:
      if (press && ctrl) {
        const bool shift = (e.mods & GLFW_MOD_SHIFT) != 0;
        if (shift ? s.Redo() : s.Undo()) Edited(app);
      }
      break;
    case GLFW_KEY_Y:
      if (press && ctrl && s.Redo()) Edited(app);
      break;
    case GLFW_KEY_ENTER:
    case GLFW_KEY_KP_ENTER:
      if (press && app->cut_tool != 0) {
        StyleOperation op = Simple(StyleOperation::Kind::kCut);
        op.cut_region = GizmoRegion(app);
        AddOperation(app, Brushed(app, op));
      }
      break;
    case GLFW_KEY_LEFT:
    case GLFW_KEY_RIGHT:
    case GLFW_KEY_UP:
    case GLFW_KEY_DOWN:
      if (press || repeat) {
        const float step = 0.05f;  // rad per press or repeat
        app->camera.Orbit(e.code == GLFW_KEY_LEFT ? step : e.code == GLFW_KEY_RIGHT ? -step : 0.0f,
                          e.code == GLFW_KEY_UP ? step : e.code == GLFW_KEY_DOWN ? -step : 0.0f);
      }
      break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD:
      if (press || repeat) app->camera.Zoom(0.9f);
      break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT:
      if (press || repeat) app->camera.Zoom(1.1f);
      break;
    default:
      break;
  }
}

// The view's part of this frame's events, in order (after ImGui::NewFrame, which says whether
// ImGui took a press: io.MouseDownOwned).
void HandleInput(App* app, const std::vector<InputEvent>& events) {
  ImGuiIO& io = ImGui::GetIO();
  const bool keyboard_free = !io.WantCaptureKeyboard;
  for (const InputEvent& e : events) {
    switch (e.kind) {
      case InputEvent::Kind::kMove:
        if (app->drag.mode != ViewDrag::Mode::kNone) ApplyDrag(app, e.x, e.y);
        break;
      case InputEvent::Kind::kButton:
        if (e.action == GLFW_PRESS && app->drag.mode == ViewDrag::Mode::kNone &&
            (e.code == GLFW_MOUSE_BUTTON_LEFT || e.code == GLFW_MOUSE_BUTTON_RIGHT ||
             e.code == GLFW_MOUSE_BUTTON_MIDDLE) &&
            !io.MouseDownOwned[e.code]) {
          ViewDrag& d = app->drag;
          d.button = e.code;
          d.x0 = e.x;
          d.y0 = e.y;
          d.mods = e.mods;
          d.camera = app->camera;
          d.plane_height = app->plane_height;
          d.plane_tilt = app->plane_tilt;
          d.plane_roll = app->plane_roll;
          d.sphere_centre_z = app->sphere_centre[2];
          d.sphere_radius = app->sphere_radius;
          // Middle drag and Alt+left drag orbit whatever tool is on.
          const bool orbit = e.code == GLFW_MOUSE_BUTTON_MIDDLE || (e.mods & GLFW_MOD_ALT) != 0;
          d.mode = e.code == GLFW_MOUSE_BUTTON_RIGHT ? ViewDrag::Mode::kPan
                   : orbit                           ? ViewDrag::Mode::kOrbit
                   : app->sculpt_tool != 0           ? ViewDrag::Mode::kSculpt
                   : app->brush_mode                 ? ViewDrag::Mode::kBrush
                   : app->cut_tool != 0              ? ViewDrag::Mode::kGizmo
                                                     : ViewDrag::Mode::kOrbit;
          if (d.mode == ViewDrag::Mode::kSculpt) SculptPress(app, e.x, e.y, e.mods);
          ApplyDrag(app, e.x, e.y);
        } else if (e.action == GLFW_RELEASE && e.code == app->drag.button &&
                   app->drag.mode != ViewDrag::Mode::kNone) {
          ApplyDrag(app, e.x, e.y);
          if (app->drag.mode == ViewDrag::Mode::kSculpt) SculptRelease(app, e.x, e.y);
          app->drag.mode = ViewDrag::Mode::kNone;
          app->drag.button = -1;
        }
        break;
      case InputEvent::Kind::kScroll:
        if (!io.WantCaptureMouse) app->camera.Zoom(std::pow(0.9f, static_cast<float>(e.y)));
        break;
      case InputEvent::Kind::kKey:
        if (keyboard_free) Shortcut(app, e);
        break;
      case InputEvent::Kind::kChar:
        break;
    }
  }
}

// --report FILE: the panel's widgets (window coordinates), the view and the document as JSON,
// written atomically after each frame that changed it (the tests read it; they act through the X
// server's input only).
void WriteReport(App* app) {
  if (app->report_path.empty()) return;
  const Session& s = app->session;
  nlohmann::ordered_json r;
  r["frame"] = app->frames;
  r["busy"] = s.Busy();
  r["up_to_date"] = s.UpToDate();
  const auto hair = s.Hair();
  r["strands"] = hair && hair->strands ? hair->strands->NumStrands() : 0;
  // The masters being solved are on screen (Session::Preview), not yet the hair.
  r["masters_preview"] = app->previewed != nullptr;
  r["message"] = app->message;
  r["modified"] = s.Modified();
  r["document"] = s.CurrentDocument().parameters;
  // The operations as the file writes them (OperationToJson).
  nlohmann::ordered_json operations = nlohmann::ordered_json::array();
  for (const StyleOperation& op : s.CurrentDocument().operations) {
    operations.push_back(OperationToJson(op));
  }
  r["document_operations"] = std::move(operations);
  r["operations"] = s.CurrentDocument().operations.size();
  r["history"] = s.HistoryLabels();
  r["history_cursor"] = s.HistoryCursor();
  const OrbitCamera& c = app->camera;
  r["camera"] = {{"yaw", c.yaw},
                 {"pitch", c.pitch},
                 {"distance", c.distance},
                 {"target", {c.target.x(), c.target.y(), c.target.z()}}};
  // Where the centre of the hair and body box is drawn (window coordinates).
  int ww, wh, fw, fh;
  WindowSize(app, &ww, &wh);
  FramebufferSize(app, &fw, &fh);
  const int x0 = PanelPixels(app);
  const Eigen::Vector4f p =
      c.Projection(static_cast<float>(std::max(1, fw - x0)) / std::max(1, fh)) * c.View() *
      app->viewer.Centre().homogeneous();
  const float scale = PixelScale(app);
  r["centre_on_screen"] = {(x0 + (0.5f + 0.5f * p.x() / p.w()) * (fw - x0)) / scale,
                           (0.5f - 0.5f * p.y() / p.w()) * fh / scale};
  r["masters_only"] = app->look.masters_only;
  r["headlight"] = app->look.headlight;
  r["fov"] = c.fov;
  r["panel_width"] = app->panel_width;
  r["field_width"] = FieldWidth();
  r["panel_content_width"] = app->panel_content_width;
  r["panel_inner_width"] = app->panel_inner_width;
  r["font_size"] = ImGui::GetFontSize();
  r["segments_drawn"] = app->viewer.DrawnSegments();
  r["segments_total"] = app->viewer.TotalSegments();
  r["master_segments"] = app->viewer.MasterSegments();
  r["preview"] = app->preview_shown;
  r["refining"] = app->refining;
  r["preview_budget"] = app->preview_budget;
  r["draw_seconds"] = app->draw_seconds;
  r["frame_cpu_seconds"] = app->frame_cpu_seconds;
  r["lines"] = app->viewer.DrewLines();
  r["body_triangles"] = {app->viewer.BodyTriangles(), app->viewer.CoarseBodyTriangles()};
  r["startup"] = app->startup;
  r["cut_tool"] = app->cut_tool;
  r["plane_height"] = app->plane_height;
  r["brush"] = s.brush.size();
  r["export_path"] = app->export_path;
  r["save_path"] = app->save_path;
  // The sculpting tools' test hooks: the tool, the masters' tips and the head centre on screen
  // (window coordinates; null when behind the eye), so the input test aims at hair and head.
  r["sculpt_tool"] = app->sculpt_tool;
  nlohmann::ordered_json tips = nlohmann::ordered_json::array();
  if (hair) {
    const StyledHair& styled = hair->styled;
    for (size_t i = 0; i < styled.masters.models.size() && i < styled.solutions.size(); ++i) {
      const Vec3 tip =
          ComputeGeometry(styled.masters.models[i], styled.solutions[i].curvatures).points.back();
      const std::optional<ImVec2> q = ViewPoint(app, tip);
      tips.push_back(q ? nlohmann::ordered_json{q->x, q->y, tip.x(), tip.y(), tip.z()}
                       : nlohmann::ordered_json(nullptr));
    }
    const std::optional<ImVec2> head = ViewPoint(app, HairstyleHead(styled.style).centre);
    r["head_on_screen"] =
        head ? nlohmann::ordered_json{head->x, head->y} : nlohmann::ordered_json(nullptr);
  }
  r["master_tips_on_screen"] = std::move(tips);
  r["widgets"] = app->widgets;
  std::string text = r.dump(1);
  if (text == app->last_report) return;
  // Replaced by a rename (readers never see half a file), without WriteFileAtomically's fsync:
  // a report is read within the second, and the fsyncs held every frame.
  const std::string temporary = app->report_path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << text << "\n";
    if (!out.flush()) {
      std::fprintf(stderr, "ringlet-studio: --report: cannot write %s\n", temporary.c_str());
      return;
    }
  }
  std::error_code ec;
  std::filesystem::rename(temporary, app->report_path, ec);
  if (ec) {
    std::fprintf(stderr, "ringlet-studio: --report: %s: %s\n", app->report_path.c_str(),
                 ec.message().c_str());
    return;
  }
  app->last_report = std::move(text);
}

// Declared here: Frame writes the F12 screenshot.
bool Screenshot(App* app, const std::string& path, std::string* error);

// One frame: sync, the events of the frame, panel, draw (the 3D view right of the panel).
void Frame(App* app) {
  const double cpu_start = ProcessCpuSeconds();
  RefreshSizes(app);
  Sync(app);
  SyncRender(app);
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  const std::vector<InputEvent> events = TakeFrameEvents(app);
  if (!events.empty()) app->redraw_frames = std::max(app->redraw_frames, 3);
  FeedImGui(app, events);
  ImGui::NewFrame();
  HandleInput(app, events);
  Panel(app);
  DrawSculptOverlay(app);
  RenderWindow(app);
  Modals(app);
  app->viewer.SetGizmo(app->cut_tool != 0 ? std::optional<CutRegion>(GizmoRegion(app))
                                          : std::nullopt);
  ImGui::Render();
  int w, h;
  FramebufferSize(app, &w, &h);
  // The preview density while the camera moves (a drag, keys, the wheel), a solve runs, or new
  // hair has just arrived; full density once still for kStillSeconds.
  const double now = glfwGetTime();
  const OrbitCamera& c = app->camera;
  const OrbitCamera& d = app->drawn_camera;
  if (c.yaw != d.yaw || c.pitch != d.pitch || c.distance != d.distance || c.fov != d.fov ||
      c.target != d.target) {
    app->last_motion = now;
  }
  const bool preview =
      app->allow_preview && (app->session.Busy() || now - app->last_motion < kStillSeconds);
  const auto draw_start = std::chrono::steady_clock::now();
  app->refining = false;
  if (preview || !app->allow_preview) {
    app->viewer.Draw(app->camera, app->look, PanelPixels(app), w, h,
                     preview ? app->preview_budget : -1);
  } else {
    // Full density, a budget of segments per frame (DrawRefining): the UI keeps up meanwhile.
    app->refining = !app->viewer.DrawRefining(app->camera, app->look, PanelPixels(app), w, h,
                                              app->preview_budget);
  }
  const long drawn = app->viewer.LastDrawSegments();
  glFinish();  // the draw's time (llvmpipe draws here; a GPU waits for a few milliseconds)
  app->draw_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - draw_start).count();
  app->drawn_camera = app->camera;
  const long full =
      app->look.masters_only ? app->viewer.MasterSegments() : app->viewer.TotalSegments();
  app->preview_shown = preview && app->viewer.DrawnSegments() < full;
  // The budget: the segments drawn in kPreviewSeconds at the measured rate.
  if (app->fixed_preview >= 0) {
    app->preview_budget = app->fixed_preview;
  } else if (drawn >= kMinPreview && app->draw_seconds > 0.0) {
    app->segments_per_second = drawn / app->draw_seconds;
    app->preview_budget = std::clamp(static_cast<long>(app->segments_per_second * kPreviewSeconds),
                                     kMinPreview, kMaxPreview);
  }
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  if (app->screenshot_key) {
    // F12: the window as drawn, to the first free studio-NNN.png of the working directory.
    app->screenshot_key = false;
    for (int n = 1; n < 1000; ++n) {
      char name[32];
      std::snprintf(name, sizeof(name), "studio-%03d.png", n);
      if (Exists(name)) continue;
      std::string error;
      if (Screenshot(app, name, &error)) {
        app->message = std::string("wrote ") + name;
      } else {
        Report(app, error);
      }
      break;
    }
  }
  ++app->frames;
  app->frame_cpu_seconds = ProcessCpuSeconds() - cpu_start;
  if (!app->first_hair_timed && app->viewer.DrawnSegments() > 0) {
    app->first_hair_timed = true;
    Phase(app, "first_hair_frame");
  }
  if (app->frames == 1) Phase(app, "first_frame");
  WriteReport(app);
  if (app->min_frame_seconds > 0.0) {
    std::this_thread::sleep_for(std::chrono::duration<double>(app->min_frame_seconds));
  }
}

// glReadPixels of the back buffer, written with the library's PNG writer (or as PPM) (sRGB bytes -> linear
// -> the writer's sRGB encoding: the bytes survive).
bool Screenshot(App* app, const std::string& path, std::string* error) {
  int w, h;
  FramebufferSize(app, &w, &h);
  std::vector<unsigned char> bytes(static_cast<size_t>(w) * h * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
  // A binary PPM (P6) for the tests: the bytes as they are, read back in a line of numpy.
  if (std::filesystem::path(path).extension() == ".ppm") {
    std::string ppm = "P6\n" + std::to_string(w) + " " + std::to_string(h) + "\n255\n";
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const unsigned char* p = &bytes[(static_cast<size_t>(h - 1 - y) * w + x) * 4];
        ppm.append(reinterpret_cast<const char*>(p), 3);
      }
    }
    return WriteFileAtomically(path, ppm, true, error);
  }
  Image image;
  image.width = w;
  image.height = h;
  image.pixels.resize(static_cast<size_t>(w) * h);
  const auto linear = [](unsigned char c) {
    const float s = c / 255.0f;
    return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const unsigned char* p = &bytes[(static_cast<size_t>(h - 1 - y) * w + x) * 4];
      image.At(x, y) = Eigen::Vector3f(linear(p[0]), linear(p[1]), linear(p[2]));
    }
  }
  return WritePng(path, image, 1.0, true, error);
}

// The interactive loop. A frame is drawn when something changed: events (and a few frames after
// them, for ImGui's layout), a solve's progress or result, a render pass, and once at full
// density after a preview (kStillSeconds after the last motion). Idle, it sleeps in
// glfwWaitEvents (no CPU); while the worker or the renderer runs, it looks at them ten times a
// second.
void RunInteractive(App* app) {
  while (!app->quit) {
    if (app->refining) app->redraw_frames = std::max(app->redraw_frames, 1);
    if (app->events.empty() && app->redraw_frames <= 0) {
      const double still_in = app->last_motion + kStillSeconds - glfwGetTime();
      if (app->session.Busy() || app->render.running) {
        glfwWaitEventsTimeout(0.1);
        app->redraw_frames = std::max(app->redraw_frames, 1);
      } else if (app->preview_shown) {
        // The full density once the view has been still for kStillSeconds.
        if (still_in > 0.0) glfwWaitEventsTimeout(still_in);
        if (app->last_motion + kStillSeconds <= glfwGetTime()) {
          app->redraw_frames = std::max(app->redraw_frames, 1);
        }
      } else {
        glfwWaitEvents();
      }
    } else {
      glfwPollEvents();
    }
    // Closing the window with unsaved changes asks first.
    if (glfwWindowShouldClose(app->window)) {
      glfwSetWindowShouldClose(app->window, GLFW_FALSE);
      Guard(app, Guarded::kQuit);
      app->redraw_frames = std::max(app->redraw_frames, 2);
      if (app->quit) break;
    }
    if (app->events.empty() && app->redraw_frames <= 0) continue;
    app->redraw_frames = std::max(0, app->redraw_frames - 1);
    Frame(app);
    glfwSwapBuffers(app->window);
  }
}

// HAIRSTYLE --screenshot OUT without --script: draws until the first solve is on screen,
// writes the frame and returns the exit code.
int FirstSolveScreenshot(App* app, const std::string& path) {
  while (app->session.Busy() || !app->session.Hair()) {
    glfwWaitEventsTimeout(0.05);
    Frame(app);
    glfwSwapBuffers(app->window);
    if (!app->session.Busy() && !app->session.Hair()) break;
  }
  const std::string solve_error = app->session.LastError();
  if (!app->session.Hair()) {
    std::fprintf(stderr, "ringlet-studio: --screenshot: no hair to show: %s\n",
                 solve_error.c_str());
    return 1;
  }
  Frame(app);  // settle the panel (ImGui lays out on the first frame)
  glfwSwapBuffers(app->window);
  Frame(app);
  std::string error;
  if (!Screenshot(app, path, &error)) {
    std::fprintf(stderr, "ringlet-studio: --screenshot: %s\n", error.c_str());
    return 1;
  }
  std::printf("screenshot: %s\n", path.c_str());
  return 0;
}

// Runs a script; returns the exit code (0, or 1 at the first failing line).
int RunScript(App* app, const std::string& script_path, const std::string& final_screenshot) {
  std::ifstream file(script_path);
  if (!file) {
    std::fprintf(stderr, "ringlet-studio: %s: cannot open the script\n", script_path.c_str());
    return 1;
  }
  std::string line;
  int number = 0;
  const auto draw = [app] {
    Frame(app);
    glfwSwapBuffers(app->window);
    glfwPollEvents();
  };
  const auto fail = [&](const std::string& text) {
    std::fprintf(stderr, "ringlet-studio: %s:%d: %s\n", script_path.c_str(), number, text.c_str());
    return 1;
  };
  while (std::getline(file, line)) {
    ++number;
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream in(line);
    std::string command;
    if (!(in >> command)) continue;
    app->message.clear();
    if (command == "open") {
      std::string path;
      in >> path;
      if (!Open(app, path)) return fail(app->message);
    } else if (command == "set") {
      std::string field, value;
      in >> field;
      std::getline(in, value);
      std::string error;
      if (!app->session.SetParameter(field, ParseValue(value), &error)) return fail(error);
      Edited(app);
    } else if (command == "brush") {
      float x, y, r;
      if (!(in >> x >> y >> r)) return fail("brush: expected X Y RADIUS (pixels)");
      app->brush_radius = r;
      Brush(app, x, y, false);
      std::printf("brush: %zu masters\n", app->session.brush.size());
    } else if (command == "brush-clear") {
      app->session.brush.clear();
      app->viewer.SetBrush({});
    } else if (command == "curl") {
      double r, p;
      if (!(in >> r >> p)) return fail("curl: expected RADIUS PITCH (m)");
      std::string error;
      if (!app->session.AddOperation(Curl(app, r, p), &error)) return fail(error);
      Edited(app);
    } else if (command == "cut-z" || command == "cut-length" || command == "cut-sphere" ||
               command == "cut-plane" || command == "cut-gizmo" || command == "wet" ||
               command == "dry" || command == "grow") {
      StyleOperation op;
      if (command == "cut-z") {
        double z;
        if (!(in >> z)) return fail("cut-z: expected Z (m)");
        op = CutZ(z);
      } else if (command == "cut-plane") {
        op = Simple(StyleOperation::Kind::kCut);
        Vec3& n = op.cut_region.normal;
        if (!(in >> n.x() >> n.y() >> n.z() >> op.cut_region.offset)) {
          return fail("cut-plane: expected NX NY NZ D");
        }
      } else if (command == "cut-gizmo") {
        if (app->cut_tool == 0) return fail("cut-gizmo: no gizmo (gizmo plane|sphere ...)");
        op = Simple(StyleOperation::Kind::kCut);
        op.cut_region = GizmoRegion(app);
      } else if (command == "cut-length") {
        op = Simple(StyleOperation::Kind::kCut);
        op.cut_region.kind = CutRegion::Kind::kMaxLength;
        if (!(in >> op.cut_region.length)) return fail("cut-length: expected L (m)");
      } else if (command == "cut-sphere") {
        op = Simple(StyleOperation::Kind::kCut);
        op.cut_region.kind = CutRegion::Kind::kInsideSphere;
        Vec3& c = op.cut_region.centre;
        if (!(in >> c.x() >> c.y() >> c.z() >> op.cut_region.radius)) {
          return fail("cut-sphere: expected X Y Z R (m)");
        }
      } else if (command == "grow") {
        op = Simple(StyleOperation::Kind::kGrow);
        if (!(in >> op.grow_step >> op.grow_steps)) return fail("grow: expected STEP STEPS");
      } else {
        op = Simple(command == "wet" ? StyleOperation::Kind::kWet : StyleOperation::Kind::kDry);
      }
      std::string error;
      if (!app->session.AddOperation(Brushed(app, op), &error)) return fail(error);
      Edited(app);
    } else if (command == "new") {
      DoGuarded(app, Guarded::kNew, "");
    } else if (command == "brush-spread") {
      int n = 0;
      if (!(in >> n) || n < 1) return fail("brush-spread: expected N >= 1");
      const auto hair = app->session.Hair();
      const int masters = hair ? static_cast<int>(hair->styled.masters.models.size()) : 0;
      if (n > masters) return fail("brush-spread: more than the " + std::to_string(masters) + " masters");
      app->session.brush.clear();
      for (int k = 0; k < n; ++k) {
        app->session.brush.push_back(static_cast<int>(static_cast<long>(k) * masters / n));
      }
      app->viewer.SetBrush(app->session.brush);
      std::printf("brush: %zu masters\n", app->session.brush.size());
    } else if (command == "gizmo") {
      std::string kind;
      in >> kind;
      if (kind == "plane") {
        app->cut_tool = 1;
        if (!(in >> app->plane_height >> app->plane_tilt >> app->plane_roll)) {
          return fail("gizmo plane: expected HEIGHT (m) TILT ROLL (degrees)");
        }
      } else if (kind == "sphere") {
        app->cut_tool = 2;
        float* c = app->sphere_centre;
        if (!(in >> c[0] >> c[1] >> c[2] >> app->sphere_radius)) {
          return fail("gizmo sphere: expected X Y Z R (m)");
        }
      } else if (kind == "off") {
        app->cut_tool = 0;
      } else {
        return fail("gizmo: expected plane, sphere or off");
      }
    } else if (command == "gizmo-drag") {
      float dy;
      if (!(in >> dy)) return fail("gizmo-drag: expected DY (pixels)");
      DragGizmo(app, 0.0f, dy, false);
      std::printf("gizmo: plane height %.4f m, sphere radius %.4f m\n", app->plane_height,
                  app->sphere_radius);
    } else if (command == "export") {
      std::string path, force;
      in >> path >> force;
      while (app->session.Busy()) draw();
      Sync(app);
      if (!DoWrite(app, Write::kExport, path, force == "force")) return fail(app->message);
      std::printf("export: %s\n", path.c_str());
    } else if (command == "render") {
      if (!(in >> app->render.width >> app->render.spp) || app->render.width < 1 ||
          app->render.spp < 1) {
        return fail("render: expected WIDTH SPP");
      }
      while (app->session.Busy()) draw();
      Sync(app);
      if (!StartRender(app)) return fail(app->message);
      // Draw while the passes arrive (the panel shows each), until the last one.
      int passes = 0, last = -1;
      while (app->render.running) {
        draw();
        if (app->render.shown_samples != last) {
          last = app->render.shown_samples;
          ++passes;
        }
      }
      app->render.Stop();
      draw();
      {
        std::lock_guard<std::mutex> lock(app->render.mutex);
        if (!app->render.error.empty()) return fail(app->render.error);
        std::printf("render: %d x %d, %d spp, %.2f s, %d passes shown\n", app->render.image.width,
                    app->render.image.height, app->render.samples, app->render.seconds, passes);
      }
    } else if (command == "save-render") {
      std::string path, force;
      in >> path >> force;
      if (!DoWrite(app, Write::kPng, path, force == "force")) return fail(app->message);
      std::printf("save-render: %s\n", path.c_str());
    } else if (command == "bench-wait") {
      // Where the time of the last edit went: the worker (solve, wisps), the upload, one frame.
      app->session.Wait();
      const double solved = glfwGetTime();
      Sync(app);
      glFinish();
      const double uploaded = glfwGetTime();
      Frame(app);
      glFinish();
      glfwSwapBuffers(app->window);
      const double drawn = glfwGetTime();
      if (const auto hair = app->session.Hair()) {
        const SolveStats& st = hair->stats;
        std::printf(
            "bench: %s, %d master solves, %d wisps regrown, solve %.3f s, wisps %.3f s, "
            "worker %.3f s, upload %.3f s (%.1f MB), draw %.3f s, edit to screen %.3f s\n",
            st.what.c_str(), st.resolved, st.regrown, st.solve_seconds, st.wisp_seconds,
            solved - app->last_edit_time, uploaded - solved,
            app->viewer.LastUploadBytes() / 1e6, drawn - uploaded, drawn - app->last_edit_time);
      }
      const std::string error = app->session.LastError();
      if (!error.empty()) return fail(error);
    } else if (command == "memory") {
      std::ifstream status("/proc/self/status");
      std::string entry;
      while (std::getline(status, entry)) {
        if (entry.rfind("VmRSS", 0) == 0 || entry.rfind("VmHWM", 0) == 0) {
          std::printf("memory: %s\n", entry.c_str());
        }
      }
    } else if (command == "undo" || command == "redo") {
      if (!(command == "undo" ? app->session.Undo() : app->session.Redo())) {
        return fail(command + ": nothing to " + command);
      }
      Edited(app);
    } else if (command == "orbit") {
      float a, b;
      if (!(in >> a >> b)) return fail("orbit: expected DYAW DPITCH (rad)");
      app->camera.Orbit(a, b);
    } else if (command == "zoom") {
      float f;
      if (!(in >> f)) return fail("zoom: expected FACTOR");
      app->camera.Zoom(f);
    } else if (command == "frame") {
      app->camera.Frame(app->viewer.Bounds());
    } else if (command == "masters") {
      std::string on;
      in >> on;
      app->look.masters_only = on == "on";
    } else if (command == "wait") {
      // Keep drawing while the worker solves (the UI never blocks), until it is done.
      while (app->session.Busy()) draw();
      draw();
      if (const auto hair = app->session.Hair()) {
        const SolveStats& s = hair->stats;
        std::printf(
            "wait: %s, %d master solves (%d kept), %ld iterations, %d unconverged, "
            "%d unstable, max penetration %.3g mm, %.3f s; edit to screen %.3f s\n",
            s.what.c_str(), s.resolved, s.reused, s.iterations, s.unconverged, s.unstable,
            s.max_penetration * 1e3, s.seconds, app->last_latency);
      }
      const std::string error = app->session.LastError();
      if (!error.empty()) return fail(error);
    } else if (command == "frames") {
      int n = 10;
      in >> n;
      glfwSwapInterval(0);
      glFinish();
      const auto start = std::chrono::steady_clock::now();
      for (int k = 0; k < n; ++k) {
        draw();
        glFinish();
      }
      const double ms =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() * 1e3 /
          std::max(1, n);
      std::printf("frames: %d frames, %.1f ms per frame, %ld segments\n", n, ms,
                  app->viewer.DrawnSegments());
    } else if (command == "screenshot") {
      std::string path, error;
      in >> path;
      draw();  // settle the panel (ImGui lays out on the first frame)
      Frame(app);
      if (!Screenshot(app, path, &error)) return fail(error);
      glfwSwapBuffers(app->window);
      std::printf("screenshot: %s\n", path.c_str());
    } else if (command == "save") {
      std::string path, force, error;
      in >> path >> force;
      if (!app->session.Save(path, &error, force == "force")) return fail(error);
      std::printf("save: %s\n", path.c_str());
    } else {
      return fail("unknown command \"" + command + "\"");
    }
    std::fflush(stdout);
    // After an edit the next command waits (and draws); drawing here would put a frame (seconds
    // under llvmpipe) inside the edit latency that bench-wait measures.
    const bool edit = command == "curl" || command == "wet" || command == "dry" ||
                      command == "grow" || command.rfind("cut-", 0) == 0 || command == "set";
    if (!edit) draw();
  }
  if (!final_screenshot.empty()) {
    while (app->session.Busy()) draw();
    draw();
    Frame(app);
    std::string error;
    if (!Screenshot(app, final_screenshot, &error)) return fail(error);
  }
  return 0;
}

int Main(int argc, char** argv) {
  SinceLaunch();  // the clock of the report's startup phases
  std::string hairstyle, script, screenshot, report;
  int width = 1280, height = 800;
  double min_frame_seconds = 0.0;
  long preview_segments = -1;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--script" && k + 1 < argc) {
      script = argv[++k];
    } else if (a == "--screenshot" && k + 1 < argc) {
      screenshot = argv[++k];
    } else if (a == "--report" && k + 1 < argc) {
      report = argv[++k];
    } else if (a == "--min-frame-seconds" && k + 1 < argc) {
      char* end = nullptr;
      min_frame_seconds = std::strtod(argv[++k], &end);
      if (!end || *end != '\0' || !(min_frame_seconds >= 0.0 && min_frame_seconds <= 10.0)) {
        std::fprintf(stderr, "ringlet-studio: --min-frame-seconds: expected seconds in [0, 10]\n");
        return 1;
      }
    } else if (a == "--preview-segments" && k + 1 < argc) {
      char* end = nullptr;
      preview_segments = std::strtol(argv[++k], &end, 10);
      if (!end || *end != '\0' || preview_segments < 0) {
        std::fprintf(stderr, "ringlet-studio: --preview-segments: expected a count >= 0\n");
        return 1;
      }
    } else if (a == "--size" && k + 1 < argc) {
      if (std::sscanf(argv[++k], "%dx%d", &width, &height) != 2 || width < 64 || height < 64) {
        std::fprintf(stderr, "ringlet-studio: --size: expected WxH (e.g. 1280x800)\n");
        return 1;
      }
    } else if (a == "-h" || a == "--help") {
      std::printf(
          "usage: ringlet-studio [HAIRSTYLE.json] [--script FILE] [--screenshot OUT.png] "
          "[--size WxH] [--report FILE] [--min-frame-seconds S] [--preview-segments N]\n"
          "  --screenshot OUT.png  with --script: the last frame; without: the first solved\n"
          "                        frame of HAIRSTYLE.json, then exit\n"
          "  --report FILE         after each frame, the widgets' rectangles and the document\n"
          "                        as JSON (for tests that drive the window with input events)\n"
          "  --min-frame-seconds S each frame lasts at least S (tests of input at low frame\n"
          "                        rates)\n"
          "  --preview-segments N  the preview density's budget of segments (while the camera\n"
          "                        moves or a solve runs); by default from the measured speed\n");
      return 0;
    } else if (!a.empty() && a[0] != '-' && hairstyle.empty()) {
      hairstyle = a;
    } else {
      std::fprintf(stderr, "ringlet-studio: unknown argument \"%s\" (see --help)\n", a.c_str());
      return 1;
    }
  }
  if (!screenshot.empty() && script.empty() && hairstyle.empty()) {
    std::fprintf(stderr,
                 "ringlet-studio: --screenshot: expected a HAIRSTYLE.json to open "
                 "(or a --script)\n");
    return 1;
  }
  // The file is read (and its body built: seconds for the head mesh's distance grid) on another
  // thread while the window and GL start.
  std::future<Session::File> reading;
  if (!hairstyle.empty()) reading = std::async(std::launch::async, Session::Read, hairstyle);
  nlohmann::ordered_json startup = nlohmann::ordered_json::object();
  const auto phase = [&startup](const char* name) {
    startup[name] = {SinceLaunch(), ProcessCpuSeconds()};
  };
  if (!glfwInit()) {
    std::fprintf(stderr, "ringlet-studio: cannot initialise GLFW (no display?)\n");
    return 1;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GL_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 4);
  GLFWwindow* window = glfwCreateWindow(width, height, "ringlet studio", nullptr, nullptr);
  if (!window) {
    std::fprintf(stderr, "ringlet-studio: cannot create an OpenGL 3.3 core window\n");
    glfwTerminate();
    return 1;
  }
  glfwMakeContextCurrent(window);
  // A software renderer (Mesa's llvmpipe) rasterizes every sample of a multisampled window:
  // 4x MSAA doubled the CPU time of a frame (docs/benchmarks.md). Without a GPU the window is
  // made again without it (the still, full-density picture is drawn off screen without MSAA
  // anyway: Viewer::DrawRefining).
  const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  if (renderer && (std::strstr(renderer, "llvmpipe") || std::strstr(renderer, "softpipe") ||
                   std::strstr(renderer, "swrast"))) {
    glfwMakeContextCurrent(nullptr);
    glfwDestroyWindow(window);
    glfwWindowHint(GLFW_SAMPLES, 0);
    window = glfwCreateWindow(width, height, "ringlet studio", nullptr, nullptr);
    if (!window) {
      std::fprintf(stderr, "ringlet-studio: cannot create an OpenGL 3.3 core window\n");
      glfwTerminate();
      return 1;
    }
    glfwMakeContextCurrent(window);
  }
  phase("window");
  glfwSwapInterval(script.empty() ? 1 : 0);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::GetIO().ConfigInputTextCursorBlink = false;  // a blinking cursor would redraw forever
  ImGui::StyleColorsDark();
  // A readable font: DejaVu Sans (fonts-dejavu-core), or ImGui's own with one line of warning.
  const ImFont* font = std::filesystem::exists(kFontPath)
                           ? ImGui::GetIO().Fonts->AddFontFromFileTTF(kFontPath, kFontPixels)
                           : nullptr;
  if (!font) {
    std::fprintf(stderr,
                 "ringlet-studio: warning: %s not found (Debian package fonts-dejavu-core): "
                 "using ImGui's default font\n",
                 kFontPath);
    ImGui::GetIO().Fonts->AddFontDefault();
  }
  // No backend callbacks: the studio's own queue every event (InstallCallbacks) and give ImGui
  // its state frame by frame (FeedImGui).
  ImGui_ImplGlfw_InitForOpenGL(window, false);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  int code = 0;
  {
    App app;
    app.window = window;
    // The worker wakes the waiting UI when it publishes masters or finishes a solve (instead of
    // the UI's next look at it, up to 0.1 s later).
    app.session.SetWake([] { glfwPostEmptyEvent(); });
    app.report_path = report;
    app.min_frame_seconds = script.empty() ? min_frame_seconds : 0.0;
    app.allow_preview = script.empty() && screenshot.empty();
    app.fixed_preview = preview_segments;
    if (preview_segments >= 0) app.preview_budget = preview_segments;
    glfwSetWindowUserPointer(window, &app);
    glfwGetCursorPos(window, &app.cursor_x, &app.cursor_y);
    InstallCallbacks(window);
    std::string error;
    phase("imgui");
    app.startup = std::move(startup);
    if (!app.viewer.Init(&error)) {
      std::fprintf(stderr, "ringlet-studio: %s\n", error.c_str());
      code = 1;
    } else {
      Phase(&app, "viewer");
      LoadLook(&app, "");
      Phase(&app, "look");
      // A file that does not open ends the scripted and screenshot modes (with its message).
      const bool opened = hairstyle.empty() || Open(&app, reading.get());
      Phase(&app, "open");
      if (!opened && (!script.empty() || !screenshot.empty())) code = 1;
      if (code == 0 && !script.empty()) {
        code = RunScript(&app, script, screenshot);
      } else if (code == 0 && !screenshot.empty()) {
        code = FirstSolveScreenshot(&app, screenshot);
      } else if (code == 0) {
        RunInteractive(&app);
      }
    }
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
  return code;
}

}  // namespace
}  // namespace ringlet::studio

int main(int argc, char** argv) { return ringlet::studio::Main(argc, argv); }
