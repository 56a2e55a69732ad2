// `ringlet-studio [HAIRSTYLE.json] [--script FILE] [--screenshot OUT.png] [--size WxH]`: the
// interactive hairstyling tool (docs/studio.md). A window with the hair and body (viewer.h), an
// ImGui panel of controls in groomers' vocabulary, a brush on the scalp, and the editing model
// (session.h) re-solving on a worker thread. --script runs a line-based script (below) and
// exits: the headless mode of the tests, under xvfb-run.
//
// Script commands, one per line (# comments): open PATH | set FIELD VALUE | brush X Y RADIUS |
// brush-clear | curl R P | cut-z Z | cut-length L | cut-sphere X Y Z R | wet | dry |
// grow STEP STEPS | undo | redo | orbit DYAW DPITCH | zoom FACTOR | frame | masters on|off |
// wait | screenshot PATH | save PATH | frames N (draw N frames, prints the mean frame time).
#include <epoxy/gl.h>
// GLFW after the GL loader.
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "ringlet/png_image.h"
#include "ringlet/render_json.h"
#include "session.h"
#include "viewer.h"

namespace ringlet::studio {
namespace {

constexpr float kPanelWidth = 360.0f;

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
  bool brush_only = true;  // curl acts on the brushed masters only (when any)
  bool framed = false;
  // Operation parameters of the panel.
  float curl_radius_mm = 8.0f, curl_pitch_mm = 20.0f;
  float cut_z = -0.15f, cut_length = 0.2f;
  float grow_step_mm = 10.0f;
  int grow_steps = 2;
  char path[512] = "";
  char save_path[512] = "styled.json";
  double last_edit_time = 0.0;  // when the last edit was made (s, glfwGetTime)
  double last_latency = 0.0;    // edit to hair on screen (s)
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
  if (!path.empty() && LoadRenderSettings(path, &settings, &error)) {
    app->look.colour = MelaninColour(settings.eumelanin, settings.pheomelanin);
  } else {
    const RenderSettings defaults;
    app->look.colour = MelaninColour(defaults.eumelanin, defaults.pheomelanin);
  }
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

StyleOperation Curl(App* app, double radius, double pitch) {
  StyleOperation op;
  op.kind = StyleOperation::Kind::kCurl;
  op.curl_radius = radius;
  op.curl_pitch = pitch;
  if (app->brush_only && !app->session.brush.empty()) op.selection.indices = app->session.brush;
  return op;
}

StyleOperation CutZ(double z) {
  StyleOperation op;
  op.kind = StyleOperation::Kind::kCut;
  op.cut_region.offset = z;
  return op;
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
    app->viewer.SetHair(hair);
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
  if (ImGui::Button("Open")) Open(app, app->path);
  ImGui::SameLine();
  ImGui::InputText("##save", app->save_path, sizeof(app->save_path));
  ImGui::SameLine();
  if (ImGui::Button("Save")) {
    std::string error;
    if (s.Save(app->save_path, &error)) {
      app->message = std::string("saved ") + app->save_path;
    } else {
      Report(app, error);
    }
  }
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
    ImGui::Text("%s: %d of %d masters re-solved (%d kept)", st.what.c_str(), st.resolved,
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
  if (ImGui::CollapsingHeader("Hair", ImGuiTreeNodeFlags_DefaultOpen)) {
    FieldCombo(app, "origin", "hair.origin", {"asian", "caucasian", "african"}, "caucasian");
    FieldCombo(app, "curl type", "hair.curl", {"straight", "wavy", "curly", "kinky"}, "wavy");
    FieldSlider(app, "length (m)", "hair.length", 0.05f, 0.8f, 0.25f);
    FieldInt(app, "hair seed", "hair.seed", 0, 100, 1);
  }
  if (ImGui::CollapsingHeader("Masters and wisps")) {
    FieldInt(app, "masters", "masters.count", 10, 3000, 1000);
    FieldInt(app, "root seed", "masters.seed", 0, 100, 0);
    FieldInt(app, "strands/wisp", "wisps.strands_per_wisp", 1, 200, 100);
    FieldSlider(app, "tip scale", "wisps.tip_scale", 0.0f, 2.0f, 0.5f);
    FieldSlider(app, "jitter (m)", "wisps.jitter", 0.0f, 0.01f, 0.0f, "%.4f");
    FieldSlider(app, "length var.", "wisps.length_variation", 0.0f, 0.5f, 0.1f);
    FieldInt(app, "hull layers", "layers.count", 1, 10, 4);
    FieldSlider(app, "layer gap (m)", "layers.thickness", 0.0f, 0.01f, 0.004f, "%.4f");
  }
  if (ImGui::CollapsingHeader("Comb")) {
    FieldSlider(app, "tilt (rad)", "comb.tilt", 0.0f, 1.5707f, 1.2f);
    FieldSlider(app, "parting offset", "comb.parting.offset", -0.08f, 0.08f, 0.0f);
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
  ImGui::Checkbox("curl the brushed masters only", &app->brush_only);
  ImGui::SliderFloat("curl radius (mm)", &app->curl_radius_mm, 1.0f, 50.0f);
  ImGui::SliderFloat("curl pitch (mm)", &app->curl_pitch_mm, -60.0f, 60.0f);
  if (ImGui::Button("Curl"))
    AddOperation(app, Curl(app, app->curl_radius_mm * 1e-3, app->curl_pitch_mm * 1e-3));
  ImGui::SameLine();
  if (ImGui::Button("Straighten")) {
    AddOperation(app, Curl(app, std::numeric_limits<double>::infinity(), 0.0));
  }
  if (ImGui::Button("Wet")) AddOperation(app, Simple(StyleOperation::Kind::kWet));
  ImGui::SameLine();
  if (ImGui::Button("Dry")) AddOperation(app, Simple(StyleOperation::Kind::kDry));
  ImGui::SliderFloat("cut height (m)", &app->cut_z, -0.4f, 0.1f);
  if (ImGui::Button("Cut below")) AddOperation(app, CutZ(app->cut_z));
  ImGui::SliderFloat("max length (m)", &app->cut_length, 0.02f, 0.8f);
  if (ImGui::Button("Cut to length")) {
    StyleOperation op = Simple(StyleOperation::Kind::kCut);
    op.cut_region.kind = CutRegion::Kind::kMaxLength;
    op.cut_region.length = app->cut_length;
    AddOperation(app, op);
  }
  ImGui::SliderFloat("grow step (mm)", &app->grow_step_mm, 1.0f, 50.0f);
  ImGui::SliderInt("grow steps", &app->grow_steps, 1, 10);
  if (ImGui::Button("Grow")) {
    StyleOperation op = Simple(StyleOperation::Kind::kGrow);
    op.grow_step = app->grow_step_mm * 1e-3;
    op.grow_steps = app->grow_steps;
    AddOperation(app, op);
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
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  HandleInput(app);
  Panel(app);
  ImGui::Render();
  int w, h;
  glfwGetFramebufferSize(app->window, &w, &h);
  app->viewer.Draw(app->camera, app->look, PanelPixels(app), w, h);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

// glReadPixels of the back buffer, written with the library's PNG writer (sRGB bytes -> linear
// -> the writer's sRGB encoding: the bytes survive).
bool Screenshot(App* app, const std::string& path, std::string* error) {
  int w, h;
  glfwGetFramebufferSize(app->window, &w, &h);
  std::vector<unsigned char> bytes(static_cast<size_t>(w) * h * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
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
               command == "wet" || command == "dry" || command == "grow") {
      StyleOperation op;
      if (command == "cut-z") {
        double z;
        if (!(in >> z)) return fail("cut-z: expected Z (m)");
        op = CutZ(z);
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
      if (!app->session.AddOperation(op, &error)) return fail(error);
      Edited(app);
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
            "wait: %s, %d masters re-solved (%d kept), %ld iterations, %d unconverged, "
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
      std::string path, error;
      in >> path;
      if (!app->session.Save(path, &error)) return fail(error);
      std::printf("save: %s\n", path.c_str());
    } else {
      return fail("unknown command \"" + command + "\"");
    }
    std::fflush(stdout);
    draw();
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
        while (!glfwWindowShouldClose(window)) {
          glfwPollEvents();
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
