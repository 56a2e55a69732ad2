// `ringlet-studio [HAIRSTYLE.json] [--script FILE] [--screenshot OUT.png] [--size WxH]`: the
// interactive hairstyling tool (docs/studio.md). A window with the hair and body (viewer.h), an
// ImGui panel of controls in groomers' vocabulary, a brush on the scalp, and the editing model
// (session.h) re-solving on a worker thread. --script runs a line-based script (below) and
// exits: the headless mode of the tests, under xvfb-run.
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

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "ringlet/atomic_file.h"
#include "ringlet/png_image.h"
#include "ringlet/render.h"
#include "ringlet/render_json.h"
#include "ringlet/render_json.h"
#include "ringlet/strand_export.h"
#include "session.h"
#include "viewer.h"

namespace ringlet::studio {
namespace {

constexpr float kPanelWidth = 360.0f;

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
  std::shared_ptr<const HairState> uploaded;
  std::string message;  // the last error or notice, shown in the panel
  bool brush_mode = false;
  float brush_radius = 30.0f;
  bool brush_only = true;  // operations act on the brushed masters only (when any)
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
  RenderPanel render;
  // Modals.
  Guarded guarded = Guarded::kNone;
  std::string guarded_path;
  bool ask_unsaved = false;
  Write replace = Write::kNone;
  std::string replace_path;
  bool ask_replace = false;
  bool quit = false;
};

// The panel's width in framebuffer pixels (the 3D view is to its right).
int PanelPixels(App* app) {
  int ww, wh, fw, fh;
  glfwGetWindowSize(app->window, &ww, &wh);
  glfwGetFramebufferSize(app->window, &fw, &fh);
  return static_cast<int>(kPanelWidth * (ww > 0 ? static_cast<float>(fw) / ww : 1.0f));
}

void Report(App* app, const std::string& text) {
  app->message = text;
  std::fprintf(stderr, "ringlet-studio: %s\n", text.c_str());
}

void Edited(App* app) { app->last_edit_time = glfwGetTime(); }

void LoadLook(App* app, const std::string& path) {
  RenderSettings settings;
  std::string error;
  if (path.empty() || !LoadRenderSettings(path, &settings, &error)) settings = RenderSettings();
  app->render_settings = settings;
  app->look.colour = MelaninColour(settings.eumelanin, settings.pheomelanin);
}

bool Open(App* app, const std::string& path) {
  std::string error;
  if (!app->session.Open(path, &error)) {
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
  glfwGetFramebufferSize(app->window, &w, &h);
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

// Takes a finished solve into the view.
void Sync(App* app) {
  app->session.Poll();
  const auto hair = app->session.Hair();
  if (hair != app->uploaded) {
    const double upload_start = glfwGetTime();
    app->viewer.SetHair(hair);
    app->last_upload = glfwGetTime() - upload_start;
    app->viewer.SetBrush(app->session.brush);
    app->uploaded = hair;
    if (!app->framed && hair) {
      app->camera.Frame(app->viewer.Bounds());
      app->framed = true;
    }
    if (app->last_edit_time > 0.0) app->last_latency = glfwGetTime() - app->last_edit_time;
  }
  const std::string error = app->session.LastError();
  if (!error.empty()) app->message = error;
}

void Brush(App* app, float x, float y, bool erase) {
  int w, h;
  glfwGetFramebufferSize(app->window, &w, &h);
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
  glfwGetFramebufferSize(app->window, &fw, &fh);
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
      ok = ExportStrands(path, *hair->strands, HairFileOptions{}, overwrite, &error);
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
      app->uploaded = nullptr;
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
  ImGui::SetNextWindowPos(ImVec2(kPanelWidth + 10.0f, 10.0f), ImGuiCond_FirstUseEver);
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

// A slider of a numeric field that edits the document when released.
void FieldSlider(App* app, const char* label, const std::string& field, float min, float max,
                 float fallback, const char* format = "%.3f") {
  const nlohmann::ordered_json v = app->session.Parameter(field);
  float value = v.is_number() ? v.get<float>() : fallback;
  ImGui::SliderFloat(label, &value, min, max, format);
  if (ImGui::IsItemDeactivatedAfterEdit()) SetField(app, field, static_cast<double>(value));
}

void FieldInt(App* app, const char* label, const std::string& field, int min, int max,
              int fallback) {
  const nlohmann::ordered_json v = app->session.Parameter(field);
  int value = v.is_number() ? v.get<int>() : fallback;
  ImGui::SliderInt(label, &value, min, max);
  if (ImGui::IsItemDeactivatedAfterEdit()) SetField(app, field, value);
}

void FieldCheckbox(App* app, const char* label, const std::string& field, bool fallback) {
  const nlohmann::ordered_json v = app->session.Parameter(field);
  bool value = v.is_boolean() ? v.get<bool>() : fallback;
  if (ImGui::Checkbox(label, &value)) SetField(app, field, value);
}

// A 3-vector field (e.g. comb.direction), edited component by component.
void FieldVector3(App* app, const char* label, const std::string& field, float min, float max,
                  const float fallback[3]) {
  const nlohmann::ordered_json v = app->session.Parameter(field);
  float value[3] = {fallback[0], fallback[1], fallback[2]};
  if (v.is_array() && v.size() == 3) {
    for (int k = 0; k < 3; ++k) {
      if (v[k].is_number()) value[k] = v[k].get<float>();
    }
  }
  ImGui::SliderFloat3(label, value, min, max, "%.2f");
  if (ImGui::IsItemDeactivatedAfterEdit()) {
    SetField(app, field, nlohmann::ordered_json::array({value[0], value[1], value[2]}));
  }
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

void Panel(App* app) {
  int w, h;
  glfwGetFramebufferSize(app->window, &w, &h);
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(kPanelWidth, static_cast<float>(h)));
  ImGui::Begin("ringlet studio", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  Session& s = app->session;
  // Files.
  ImGui::InputText("file", app->path, sizeof(app->path));
  if (ImGui::Button("Open")) Guard(app, Guarded::kOpen, app->path);
  ImGui::SameLine();
  if (ImGui::Button("New")) Guard(app, Guarded::kNew);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(150.0f);
  ImGui::InputText("##save", app->save_path, sizeof(app->save_path));
  ImGui::SameLine();
  if (ImGui::Button("Save")) {
    // The document's own file is replaced; any other existing file is asked about.
    if (app->save_path == s.Path()) {
      DoWrite(app, Write::kSave, app->save_path, true);
    } else {
      TryWrite(app, Write::kSave, app->save_path);
    }
  }
  ImGui::SetNextItemWidth(200.0f);
  ImGui::InputText("##export", app->export_path, sizeof(app->export_path));
  ImGui::SameLine();
  if (ImGui::Button("Export (.hair/.usda/.obj)")) TryWrite(app, Write::kExport, app->export_path);
  if (ImGui::Button("Render...")) {
    app->render.open = true;
    if (!app->render.running) StartRender(app);
  }
  ImGui::SameLine();
  if (ImGui::Button("Undo") || (ImGui::IsKeyPressed(GLFW_KEY_Z) && ImGui::GetIO().KeyCtrl)) {
    if (s.Undo()) Edited(app);
  }
  ImGui::SameLine();
  if (ImGui::Button("Redo") || (ImGui::IsKeyPressed(GLFW_KEY_Y) && ImGui::GetIO().KeyCtrl)) {
    if (s.Redo()) Edited(app);
  }
  ImGui::SameLine();
  ImGui::Text("%s", s.Modified() ? "(unsaved changes)" : "");

  // Solve status.
  ImGui::Separator();
  int done = 0, total = 0;
  std::string what;
  s.Progress(&done, &total, &what);
  if (s.Busy()) {
    ImGui::ProgressBar(total > 0 ? static_cast<float>(done) / total : 0.0f, ImVec2(-1, 0),
                       what.c_str());
  } else {
    ImGui::ProgressBar(1.0f, ImVec2(-1, 0), "solved");
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
  }
  if (!app->message.empty()) ImGui::TextWrapped("%s", app->message.c_str());

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
      FieldSlider(app, label.c_str(), field, 0.05f, 0.8f, 0.25f);
    }
    ImGui::EndDisabled();
    FieldInt(app, "hair seed", "hair.seed", 0, 100, 1);
    // The section and the natural curl in the groomer's terms (hair.ellipticity,
    // hair.curl_radius, hair.curl_pitch, hair.curl_spread), shown at the hair type's values
    // until set.
    if (const auto hair = s.Hair()) {
      const HairType& type = hair->styled.style.hair_type;
      FieldSlider(app, "a/b", "hair.ellipticity", 1.0f, 3.0f,
                  static_cast<float>(type.ellipticity));
      ImGui::BeginDisabled(type.IsStraight());  // no helix to size (the reader refuses it)
      FieldSlider(app, "natural R (m)", "hair.curl_radius", 0.0005f, 0.1f,
                  type.IsStraight() ? 0.0f : static_cast<float>(type.curl_radius), "%.4f");
      FieldSlider(app, "natural pitch (m)", "hair.curl_pitch", 0.0f, 0.2f,
                  type.IsStraight() ? 0.0f : static_cast<float>(type.curl_pitch), "%.4f");
      FieldSlider(app, "curl spread", "hair.curl_spread", 0.0f, 1.0f,
                  type.IsStraight() ? 0.0f
                                    : static_cast<float>(type.curl_radius_std / type.curl_radius));
      ImGui::EndDisabled();
    }
  }
  if (ImGui::CollapsingHeader("Masters and wisps")) {
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
      FieldSlider(app, "wisp radius (m)", "wisps.radius", 0.0005f, 0.02f,
                  static_cast<float>(mean), "%.4f");
      ImGui::SameLine();
      if (ImGui::SmallButton("auto")) SetField(app, "wisps.radius", "auto");
    }
    FieldSlider(app, "tip scale", "wisps.tip_scale", 0.0f, 2.0f, 0.5f);
    FieldSlider(app, "jitter (m)", "wisps.jitter", 0.0f, 0.01f, 0.0f, "%.4f");
    FieldSlider(app, "length var.", "wisps.length_variation", 0.0f, 0.5f, 0.1f);
    FieldInt(app, "hull layers", "layers.count", 1, 10, 4);
    FieldSlider(app, "layer gap (m)", "layers.thickness", 0.0f, 0.01f, 0.004f, "%.4f");
  }
  if (ImGui::CollapsingHeader("Comb")) {
    ImGui::BeginDisabled(explicit_masters);
    const float down[3] = {0.0f, 0.0f, -1.0f};
    FieldVector3(app, "direction", "comb.direction", -1.0f, 1.0f, down);
    FieldSlider(app, "tilt (rad)", "comb.tilt", 0.0f, 1.5707f, 1.2f);
    FieldSlider(app, "face sweep", "comb.face_sweep", 0.0f, 2.0f, 0.0f);
    FieldSlider(app, "parting offset", "comb.parting.offset", -0.08f, 0.08f, 0.0f);
    FieldCheckbox(app, "waves laid into the head", "comb.curl_inward", false);
    ImGui::EndDisabled();
  }

  // Operations.
  ImGui::Separator();
  ImGui::Text("Styling");
  ImGui::Checkbox("brush (paint roots: left drag, ctrl erases)", &app->brush_mode);
  ImGui::SliderFloat("brush radius (px)", &app->brush_radius, 5.0f, 150.0f);
  ImGui::Text("%zu masters brushed", s.brush.size());
  ImGui::SameLine();
  if (ImGui::Button("clear")) {
    s.brush.clear();
    app->viewer.SetBrush(s.brush);
  }
  ImGui::Checkbox("operations act on the brushed masters only", &app->brush_only);
  ImGui::SliderFloat("curl radius (mm)", &app->curl_radius_mm, 1.0f, 50.0f);
  ImGui::SliderFloat("curl pitch (mm)", &app->curl_pitch_mm, -60.0f, 60.0f);
  if (ImGui::Button("Curl"))
    AddOperation(app, Curl(app, app->curl_radius_mm * 1e-3, app->curl_pitch_mm * 1e-3));
  ImGui::SameLine();
  if (ImGui::Button("Straighten")) {
    AddOperation(app, Curl(app, std::numeric_limits<double>::infinity(), 0.0));
  }
  if (ImGui::Button("Wet")) AddOperation(app, Brushed(app, Simple(StyleOperation::Kind::kWet)));
  ImGui::SameLine();
  if (ImGui::Button("Dry")) AddOperation(app, Brushed(app, Simple(StyleOperation::Kind::kDry)));
  ImGui::Text("cut tool (drag in the view; shift tilts):");
  ImGui::RadioButton("off", &app->cut_tool, 0);
  ImGui::SameLine();
  ImGui::RadioButton("plane", &app->cut_tool, 1);
  ImGui::SameLine();
  ImGui::RadioButton("sphere", &app->cut_tool, 2);
  if (app->cut_tool == 1) {
    ImGui::SliderFloat("plane height (m)", &app->plane_height, -0.5f, 0.2f);
    ImGui::SliderFloat("tilt (deg)", &app->plane_tilt, -80.0f, 80.0f);
    ImGui::SliderFloat("roll (deg)", &app->plane_roll, -80.0f, 80.0f);
  } else if (app->cut_tool == 2) {
    ImGui::SliderFloat3("centre (m)", app->sphere_centre, -0.3f, 0.3f);
    ImGui::SliderFloat("radius (m)", &app->sphere_radius, 0.02f, 0.6f);
  }
  if (app->cut_tool != 0 && (ImGui::Button("Apply cut (Enter)") ||
                             (!ImGui::GetIO().WantCaptureKeyboard &&
                              ImGui::IsKeyPressed(GLFW_KEY_ENTER)))) {
    StyleOperation op = Simple(StyleOperation::Kind::kCut);
    op.cut_region = GizmoRegion(app);
    AddOperation(app, Brushed(app, op));
  }
  ImGui::SliderFloat("cut height (m)", &app->cut_z, -0.4f, 0.1f);
  if (ImGui::Button("Cut below")) AddOperation(app, Brushed(app, CutZ(app->cut_z)));
  ImGui::SliderFloat("max length (m)", &app->cut_length, 0.02f, 0.8f);
  if (ImGui::Button("Cut to length")) {
    StyleOperation op = Simple(StyleOperation::Kind::kCut);
    op.cut_region.kind = CutRegion::Kind::kMaxLength;
    op.cut_region.length = app->cut_length;
    AddOperation(app, Brushed(app, op));
  }
  ImGui::SliderFloat("grow step (mm)", &app->grow_step_mm, 1.0f, 50.0f);
  ImGui::SliderInt("grow steps", &app->grow_steps, 1, 10);
  if (ImGui::Button("Grow")) {
    StyleOperation op = Simple(StyleOperation::Kind::kGrow);
    op.grow_step = app->grow_step_mm * 1e-3;
    op.grow_steps = app->grow_steps;
    AddOperation(app, Brushed(app, op));
  }

  // View.
  ImGui::Separator();
  ImGui::Checkbox("masters only", &app->look.masters_only);
  ImGui::SameLine();
  ImGui::Checkbox("highlight masters", &app->look.highlight_masters);
  ImGui::TextWrapped(
      "Mouse: left orbit, right pan, wheel zoom. Keys: F frame all, arrows orbit, +/- zoom, "
      "M masters. Red: unconverged, magenta: unstable, cyan: brushed.");
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

void HandleInput(App* app) {
  ImGuiIO& io = ImGui::GetIO();
  static double last_x = 0, last_y = 0;
  double x, y;
  glfwGetCursorPos(app->window, &x, &y);
  int ww, wh, fw, fh;
  glfwGetWindowSize(app->window, &ww, &wh);
  glfwGetFramebufferSize(app->window, &fw, &fh);
  const float scale = ww > 0 ? static_cast<float>(fw) / ww : 1.0f;
  const float dx = static_cast<float>(x - last_x), dy = static_cast<float>(y - last_y);
  last_x = x;
  last_y = y;
  if (!io.WantCaptureMouse) {
    const bool left = glfwGetMouseButton(app->window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    const bool right = glfwGetMouseButton(app->window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
    if (left && app->brush_mode) {
      Brush(app, static_cast<float>(x) * scale, static_cast<float>(y) * scale, io.KeyCtrl);
    } else if (left && app->cut_tool != 0) {
      DragGizmo(app, dx * scale, dy * scale, io.KeyShift);
    } else if (left) {
      app->camera.Orbit(-dx * 0.008f, dy * 0.008f);
    }
    if (right) app->camera.Pan(-dx * 0.0015f, dy * 0.0015f);
    if (io.MouseWheel != 0.0f) app->camera.Zoom(std::pow(0.9f, io.MouseWheel));
  }
  if (!io.WantCaptureKeyboard) {
    if (ImGui::IsKeyPressed(GLFW_KEY_F)) app->camera.Frame(app->viewer.Bounds());
    if (ImGui::IsKeyPressed(GLFW_KEY_M)) app->look.masters_only = !app->look.masters_only;
    if (ImGui::IsKeyDown(GLFW_KEY_LEFT)) app->camera.Orbit(0.03f, 0.0f);
    if (ImGui::IsKeyDown(GLFW_KEY_RIGHT)) app->camera.Orbit(-0.03f, 0.0f);
    if (ImGui::IsKeyDown(GLFW_KEY_UP)) app->camera.Orbit(0.0f, 0.03f);
    if (ImGui::IsKeyDown(GLFW_KEY_DOWN)) app->camera.Orbit(0.0f, -0.03f);
    if (ImGui::IsKeyPressed(GLFW_KEY_EQUAL) || ImGui::IsKeyPressed(GLFW_KEY_KP_ADD)) {
      app->camera.Zoom(0.9f);
    }
    if (ImGui::IsKeyPressed(GLFW_KEY_MINUS) || ImGui::IsKeyPressed(GLFW_KEY_KP_SUBTRACT)) {
      app->camera.Zoom(1.1f);
    }
  }
}

// One frame: sync, panel, draw (the 3D view to the right of the panel).
void Frame(App* app) {
  Sync(app);
  SyncRender(app);
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  HandleInput(app);
  Panel(app);
  RenderWindow(app);
  Modals(app);
  app->viewer.SetGizmo(app->cut_tool != 0 ? std::optional<CutRegion>(GizmoRegion(app))
                                          : std::nullopt);
  ImGui::Render();
  int w, h;
  glfwGetFramebufferSize(app->window, &w, &h);
  app->viewer.Draw(app->camera, app->look, PanelPixels(app), w, h);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

// glReadPixels of the back buffer, written with the library's PNG writer (or as PPM) (sRGB bytes -> linear
// -> the writer's sRGB encoding: the bytes survive).
bool Screenshot(App* app, const std::string& path, std::string* error) {
  int w, h;
  glfwGetFramebufferSize(app->window, &w, &h);
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
  std::string hairstyle, script, screenshot;
  int width = 1280, height = 800;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--script" && k + 1 < argc) {
      script = argv[++k];
    } else if (a == "--screenshot" && k + 1 < argc) {
      screenshot = argv[++k];
    } else if (a == "--size" && k + 1 < argc) {
      if (std::sscanf(argv[++k], "%dx%d", &width, &height) != 2 || width < 64 || height < 64) {
        std::fprintf(stderr, "ringlet-studio: --size: expected WxH (e.g. 1280x800)\n");
        return 1;
      }
    } else if (a == "-h" || a == "--help") {
      std::printf(
          "usage: ringlet-studio [HAIRSTYLE.json] [--script FILE] [--screenshot OUT.png] "
          "[--size WxH]\n");
      return 0;
    } else if (!a.empty() && a[0] != '-' && hairstyle.empty()) {
      hairstyle = a;
    } else {
      std::fprintf(stderr, "ringlet-studio: unknown argument \"%s\" (see --help)\n", a.c_str());
      return 1;
    }
  }
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
  glfwSwapInterval(script.empty() ? 1 : 0);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  int code = 0;
  {
    App app;
    app.window = window;
    std::string error;
    if (!app.viewer.Init(&error)) {
      std::fprintf(stderr, "ringlet-studio: %s\n", error.c_str());
      code = 1;
    } else {
      LoadLook(&app, "");
      if (!hairstyle.empty() && !Open(&app, hairstyle) && !script.empty()) code = 1;
      if (code == 0 && !script.empty()) {
        code = RunScript(&app, script, screenshot);
      } else if (code == 0) {
        while (!app.quit) {
          glfwPollEvents();
          // Closing the window with unsaved changes asks first.
          if (glfwWindowShouldClose(window)) {
            glfwSetWindowShouldClose(window, GLFW_FALSE);
            Guard(&app, Guarded::kQuit);
            if (app.quit) break;
          }
          Frame(&app);
          glfwSwapBuffers(window);
        }
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
