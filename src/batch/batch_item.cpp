// Running one batch item (batch.h, docs/batch.md): groom, operations, strands, views and labels,
// all encoded in memory; nothing here depends on the run, the thread count or the time (except
// the timing record, kept apart).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "ringlet/batch.h"
#include "ringlet/hair_file.h"
#include "ringlet/hairstyle.h"
#include "ringlet/hairstyle_json.h"
#include "ringlet/png_image.h"
#include "ringlet/render.h"
#include "ringlet/render_json.h"
#include "ringlet/styling.h"
#include "ringlet/usc_data.h"
#include "ringlet/usd_export.h"

namespace ringlet {
namespace {

using nlohmann::json;

// Strands are traced at least one pixel wide for the labels (RenderLabelMaps).
constexpr double kLabelWidthPixels = 1.0;

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

HairCurves ResampleStrands(const HairCurves& in, int n) {
  HairCurves out;
  out.colors = in.colors;
  out.wetness = in.wetness;
  out.point_counts.assign(in.point_counts.size(), static_cast<std::uint32_t>(n));
  out.points.reserve(in.point_counts.size() * static_cast<size_t>(n));
  out.widths.reserve(out.points.capacity());
  size_t first = 0;
  std::vector<double> arc;
  for (const std::uint32_t count : in.point_counts) {
    arc.assign(count, 0.0);
    for (std::uint32_t i = 1; i < count; ++i) {
      arc[i] = arc[i - 1] + (in.points[first + i] - in.points[first + i - 1]).cast<double>().norm();
    }
    const double length = arc.back();
    std::uint32_t segment = 0;
    for (int j = 0; j < n; ++j) {
      const double s = j == n - 1 ? length : length * j / (n - 1);
      while (segment + 2 < count && arc[segment + 1] < s) ++segment;
      const double span = arc[segment + 1] - arc[segment];
      const double t = span > 0.0 ? std::clamp((s - arc[segment]) / span, 0.0, 1.0) : 0.0;
      const Eigen::Vector3d a = in.points[first + segment].cast<double>();
      const Eigen::Vector3d b = in.points[first + segment + 1].cast<double>();
      out.points.push_back((a + t * (b - a)).cast<float>());
      const double wa = in.widths[first + segment], wb = in.widths[first + segment + 1];
      out.widths.push_back(static_cast<float>(wa + t * (wb - wa)));
    }
    first += count;
  }
  return out;
}

namespace {

// A NumPy .npy file (format version 1.0, https://numpy.org/doc/stable/reference/generated/
// numpy.lib.format.html) of little-endian float32 values of shape (height, width).
std::string EncodeNpyFloat32(const std::vector<float>& values, int width, int height) {
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" +
                       std::to_string(height) + ", " + std::to_string(width) + "), }";
  // Magic (6) + version (2) + header length (2) + header + padding + '\n': a multiple of 64.
  const size_t total = 10 + header.size() + 1;
  header.append((64 - total % 64) % 64, ' ');
  header.push_back('\n');
  std::string bytes("\x93NUMPY\x01\x00", 8);
  bytes.push_back(static_cast<char>(header.size() & 0xff));
  bytes.push_back(static_cast<char>(header.size() >> 8));
  bytes += header;
  for (const float v : values) {
    std::uint32_t u = 0;
    std::memcpy(&u, &v, 4);
    for (int k = 0; k < 4; ++k) bytes.push_back(static_cast<char>((u >> (8 * k)) & 0xff));
  }
  return bytes;
}

// "05": view numbers with at least 2 digits.
std::string ViewNumber(size_t v) { return (v < 10 ? "0" : "") + std::to_string(v); }

}  // namespace

const char* BatchStatusName(BatchItemResult::Status status) {
  switch (status) {
    case BatchItemResult::Status::kDone:
      return "done";
    case BatchItemResult::Status::kFlagged:
      return "flagged";
    case BatchItemResult::Status::kFailed:
      return "failed";
  }
  return "failed";
}

BatchItemResult RunBatchItem(const BatchSpec& spec, const BatchItem& item, int threads,
                             const std::atomic<bool>* cancel) {
  BatchItemResult result;
  const auto start = std::chrono::steady_clock::now();
  const auto failed = [&](const std::string& why) {
    result.status = BatchItemResult::Status::kFailed;
    result.error = why;
    result.files.clear();
    return result;
  };
  try {
    std::vector<std::pair<std::string, std::string>> files;
    files.emplace_back("hairstyle.json", item.hairstyle.dump(1) + "\n");
    Hairstyle style;
    std::vector<StyleOperation> operations;
    RenderSettings settings;
    std::string why;
    // The base's body as read by the spec check (null for a spec made by hand: read it).
    const std::shared_ptr<const Body> body =
        static_cast<size_t>(item.base) < spec.bodies.size() ? spec.bodies[item.base] : nullptr;
    if (!ParseHairstyle(item.hairstyle, spec.directory, body, &style, &why) ||
        !ParseStyleOperations(item.hairstyle, &operations, &why) ||
        !ParseRenderMember(item.hairstyle, &settings, &why)) {
      return failed("hairstyle: " + why);
    }
    BatchOptions batch;
    batch.threads = threads;
    batch.cancel = cancel;
    Groom groom;
    const auto groom_start = std::chrono::steady_clock::now();
    if (!GroomHairstyle(style, batch, &groom, &why)) return failed("groom: " + why);
    const double groom_seconds = SecondsSince(groom_start);
    const GroomSummary summary = groom.summary;
    const std::string roots = groom.masters.root_summary.message;

    // The operations, as `ringlet style` runs them.
    const auto style_start = std::chrono::steady_clock::now();
    HairCurves strands;
    int styled_unconverged = 0, styled_unstable = 0;
    json reports = json::array();
    if (operations.empty()) {
      strands = std::move(groom.strands);
    } else {
      StyledHair state;
      if (!MakeStyledHair(style, groom, &state, &why)) return failed("style: " + why);
      groom = Groom{};
      for (size_t k = 0; k < operations.size(); ++k) {
        const StyleOperation& op = operations[k];
        const std::string from = "operations[" + std::to_string(k) + "]";
        if (!op.selection.IsValid(static_cast<int>(state.masters.models.size()), &why)) {
          return failed(from + ": " + why);
        }
        OperationReport report;
        if (!ApplyOperation(&state, op, batch, nullptr, &report, &why)) {
          return failed(from + ": " + why);
        }
        reports.push_back(json{{"name", report.name},
                               {"strands", report.strands},
                               {"iterations", report.iterations},
                               {"rounds", report.rounds},
                               {"unconverged", report.unconverged}});
      }
      for (const StrandSolution& s : state.solutions) {
        if (!s.summary.Converged()) {
          ++styled_unconverged;
        } else if (s.summary.stability_checked && !s.summary.stable) {
          ++styled_unstable;
        }
      }
      if (!StyledStrands(state, &strands, &why)) return failed("style: " + why);
    }
    const double style_seconds = SecondsSince(style_start);
    SetMelaninColours(settings, &strands);

    // Strand files.
    HairCurves resampled;
    if (spec.outputs.points_per_strand > 0) {
      resampled = ResampleStrands(strands, spec.outputs.points_per_strand);
    }
    const HairCurves& written = spec.outputs.points_per_strand > 0 ? resampled : strands;
    json file_names = json::array();
    if (spec.outputs.hair) {
      std::string bytes;
      if (!EncodeHairFile(written, HairFileOptions{}, &bytes, &why)) {
        return failed("strands.hair: " + why);
      }
      files.emplace_back("strands.hair", std::move(bytes));
    }
    if (spec.outputs.usda) {
      std::string text;
      if (!EncodeUsda(written, UsdExportOptions{}, &text, &why)) {
        return failed("strands.usda: " + why);
      }
      files.emplace_back("strands.usda", std::move(text));
    }
    if (spec.outputs.data) {
      StrandTargetOptions usc;
      usc.up_axis = StrandTargetOptions::UpAxis::kY;  // the database's convention: metres, y up
      std::string bytes;
      if (!EncodeUscData(written, usc, &bytes, &why)) return failed("strands.data: " + why);
      files.emplace_back("strands.data", std::move(bytes));
    }

    // Views: the item's render settings with the spec's image size and each view's camera.
    const auto render_start = std::chrono::steady_clock::now();
    json views = json::array();
    if (spec.outputs.images) {
      std::vector<json> cameras = spec.views;
      if (cameras.empty()) cameras.push_back(nullptr);  // the hairstyle's own camera
      for (size_t v = 0; v < cameras.size(); ++v) {
        json render = item.hairstyle.contains("render") ? item.hairstyle["render"] : json::object();
        render["width"] = spec.outputs.width;
        render["height"] = spec.outputs.height;
        render["samples_per_pixel"] = spec.outputs.samples_per_pixel;
        if (!cameras[v].is_null()) render["camera"] = cameras[v];
        RenderSettings view_settings;
        if (!ParseRenderSettings(render, "render", &view_settings, &why)) {
          return failed("view " + std::to_string(v) + ": " + why);
        }
        RenderScene scene;
        if (!MakeRenderScene(view_settings, &strands, style.body,
                             HairTypeEccentricity(style.hair_type), style.seed, &scene, &why)) {
          return failed("view " + std::to_string(v) + ": " + why);
        }
        RenderOptions options = view_settings.options;
        options.threads = threads;
        options.cancel = cancel;
        Image image;
        RenderStats stats;
        if (!Render(scene, options, &image, &stats, &why)) {
          return failed("view " + std::to_string(v) + ": render: " + why);
        }
        const std::string number = ViewNumber(v);
        std::string png;
        if (!EncodePng(image, view_settings.exposure, &png, &why)) {
          return failed("rgb_" + number + ".png: " + why);
        }
        files.emplace_back("rgb_" + number + ".png", std::move(png));
        if (spec.outputs.labels) {
          RenderLabels labels;
          if (!RenderLabelMaps(scene, options, kLabelWidthPixels, &labels, &why)) {
            return failed("view " + std::to_string(v) + ": labels: " + why);
          }
          const size_t pixels = labels.hair.size();
          std::vector<unsigned char> mask(pixels), orientation(3 * pixels);
          for (size_t i = 0; i < pixels; ++i) {
            mask[i] = labels.hair[i] ? 255 : 0;
            if (!labels.hair[i]) continue;
            // HairStep's strand map (Zheng et al., CVPR 2023): R the mask, G and B the unit 2D
            // direction (x right, y up) mapped from [-1, 1] to [0, 255].
            orientation[3 * i] = 255;
            for (int c = 0; c < 2; ++c) {
              orientation[3 * i + 1 + static_cast<size_t>(c)] = static_cast<unsigned char>(
                  std::lround(127.5 * (1.0 + static_cast<double>(labels.direction[i][c]))));
            }
          }
          std::string mask_png, orientation_png;
          if (!EncodePngCodes(mask, labels.width, labels.height, 1, &mask_png, &why) ||
              !EncodePngCodes(orientation, labels.width, labels.height, 3, &orientation_png,
                              &why)) {
            return failed("view " + std::to_string(v) + ": labels: " + why);
          }
          files.emplace_back("mask_" + number + ".png", std::move(mask_png));
          files.emplace_back("orientation_" + number + ".png", std::move(orientation_png));
          files.emplace_back("depth_" + number + ".npy",
                             EncodeNpyFloat32(labels.depth, labels.width, labels.height));
        }
        const Camera& c = scene.camera;
        views.push_back(json{{"camera",
                              {{"position", {c.position.x(), c.position.y(), c.position.z()}},
                               {"look_at", {c.look_at.x(), c.look_at.y(), c.look_at.z()}},
                               {"up", {c.up.x(), c.up.y(), c.up.z()}},
                               {"fov_degrees", c.vertical_fov * 180.0 / M_PI}}},
                             {"width", image.width},
                             {"height", image.height},
                             {"samples_per_pixel", options.samples_per_pixel}});
      }
    }
    const double render_seconds = SecondsSince(render_start);

    const bool flagged = summary.unconverged + summary.unstable + summary.children_unconverged +
                             summary.children_unstable + styled_unconverged + styled_unstable >
                         0;
    result.status = flagged ? BatchItemResult::Status::kFlagged : BatchItemResult::Status::kDone;
    for (const auto& f : files) file_names.push_back(f.first);
    json metadata = {{"item", item.index},
                     {"name", item.name},
                     {"status", BatchStatusName(result.status)},
                     {"parameters", item.parameters},
                     {"groom",
                      {{"masters", summary.masters},
                       {"strands", summary.strands},
                       {"points", summary.points},
                       {"converged", summary.converged},
                       {"unconverged", summary.unconverged},
                       {"unstable", summary.unstable},
                       {"iterations", summary.iterations},
                       {"max_penetration", summary.max_penetration},
                       {"children_solved", summary.children_solved},
                       {"children_unconverged", summary.children_unconverged},
                       {"children_unstable", summary.children_unstable},
                       {"roots", roots}}},
                     {"style",
                      {{"operations", reports},
                       {"unconverged", styled_unconverged},
                       {"unstable", styled_unstable}}},
                     {"strands",
                      {{"strands", written.NumStrands()},
                       {"points", written.NumPoints()},
                       {"points_per_strand", spec.outputs.points_per_strand}}},
                     {"views", views},
                     {"files", file_names}};
    files.emplace_back("metadata.json", metadata.dump(1) + "\n");
    result.files = std::move(files);
    result.timing = json{{"groom_seconds", groom_seconds},
                         {"style_seconds", style_seconds},
                         {"render_seconds", render_seconds},
                         {"total_seconds", SecondsSince(start)}};
    return result;
  } catch (const std::exception& e) {
    return failed(std::string("unexpected error: ") + e.what());
  }
}

}  // namespace ringlet
