// The renderer (render.h, render_json.h, png_image.h) for the Python module; docs/python.md.
#include <pybind11/stl.h>

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bindings.h"
#include "ringlet/body_json.h"
#include "ringlet/png_image.h"
#include "ringlet/render.h"
#include "ringlet/render_json.h"
#include "types.h"

namespace ringlet::python {

namespace {

// An image's pixels as an (H, W, 3) float32 array owning the storage (no copy).
py::array ImageArray(Image&& image) {
  const py::ssize_t h = image.height, w = image.width;
  static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float));
  auto* owned = new Image(std::move(image));
  py::capsule owner(owned, [](void* p) { delete static_cast<Image*>(p); });
  return py::array(py::dtype::of<float>(), {h, w, py::ssize_t{3}},
                   {w * py::ssize_t{12}, py::ssize_t{12}, py::ssize_t{4}},
                   owned->pixels.empty() ? nullptr : owned->pixels[0].data(), owner);
}

// An (H, W, 3) array-like of linear radiance as an Image (copied). Integer arrays are refused:
// they are sRGB codes (render(srgb=True), encode_srgb8), which a cast to float would take as
// radiance 0..255 and write as an all-white PNG.
Image ImageFrom(const py::handle& array) {
  py::array any = py::module_::import("numpy").attr("asarray")(array);
  const char kind = any.dtype().kind();
  if (kind != 'f') {
    throw Error("image: expected linear radiance, a floating-point array of shape (height, "
                "width, 3), got dtype " + std::string(py::str(any.dtype())) +
                (kind == 'u' || kind == 'i'
                     ? " (8-bit sRGB codes, as render(srgb=True) returns, are already encoded: "
                       "pass the linear image, render(srgb=False))"
                     : ""));
  }
  auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(any);
  if (!a || a.ndim() != 3 || a.shape(2) != 3) {
    throw Error("image: expected an array of shape (height, width, 3)");
  }
  Image image;
  if (a.shape(0) * a.shape(1) > kMaxRenderPixels) {
    throw Error("image: expected at most " + std::to_string(kMaxRenderPixels) +
                " pixels (kMaxRenderPixels), got " + std::to_string(a.shape(0)) + " x " +
                std::to_string(a.shape(1)));
  }
  image.height = static_cast<int>(a.shape(0));
  image.width = static_cast<int>(a.shape(1));
  image.pixels.resize(static_cast<size_t>(image.width) * image.height);
  const float* data = a.data();
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    image.pixels[i] = Eigen::Vector3f(data[3 * i], data[3 * i + 1], data[3 * i + 2]);
  }
  return image;
}

}  // namespace

void BindRender(py::module_& m) {
  py::class_<RenderStats>(m, "RenderStats", "What a render did (render.h).")
      .def_readonly("seconds", &RenderStats::seconds, "Wall time (s).")
      .def_readonly("build_seconds", &RenderStats::build_seconds, "Embree scene build (s).")
      .def_readonly("camera_rays", &RenderStats::camera_rays, "Camera rays.")
      .def_readonly("rays", &RenderStats::rays, "All rays traced.")
      .def_readonly("nan_samples", &RenderStats::nan_samples,
                    "Samples discarded as NaN or infinite (reported, never hidden).")
      .def_readonly("hair_segments", &RenderStats::hair_segments, "Curve segments traced.")
      .def_readonly("body_primitives", &RenderStats::body_primitives, "Spheres + triangles.");

  m.def(
      "render",
      [](py::object hair, py::object hairstyle, py::object settings, py::object body_arg,
         std::optional<long long> width, std::optional<long long> height,
         std::optional<long long> samples_per_pixel, std::optional<double> eccentricity, long long threads,
         bool srgb, bool return_stats) {
        // What to render: a Groom brings its strands and hairstyle.
        std::shared_ptr<const HairstyleFile> style;
        const HairCurves* curves = nullptr;
        if (py::isinstance<GroomResult>(hair)) {
          const auto& g = hair.cast<const GroomResult&>();
          curves = &g.groom.strands;
          style = g.hairstyle;
        } else if (!hair.is_none()) {
          curves = &hair.cast<const HairCurves&>();
        }
        if (curves) {
          // The views are writable: counts edited in place must not send the renderer's
          // framing past the points.
          std::string why;
          if (!CheckHairCurves(*curves, "hair", &why)) throw Error(why);
        }
        if (!hairstyle.is_none()) style = HairstyleFrom(hairstyle, ".");
        RenderSettings s;
        if (style) s = style->render;
        std::string error;
        if (!settings.is_none()) {
          s = RenderSettings{};
          if (!ParseRenderSettings(ToJson(settings, "render"), "render", &s, &error)) {
            throw Error(error);
          }
        }
        // The overrides take what `ringlet render` --width, --height and --spp take (CLI::Range
        // in cli/render_command.cpp, the settings' own limits), then the products are checked
        // (CheckRenderSize) as the command checks them.
        const auto override_int = [](const std::optional<long long>& value, const char* field,
                                     long long max, int* target) {
          if (!value) return;
          if (*value < 1 || *value > max) {
            throw Error(std::string(field) + ": expected an integer between 1 and " +
                        std::to_string(max) + ", got " + std::to_string(*value));
          }
          *target = static_cast<int>(*value);
        };
        override_int(width, "width", 16384, &s.options.width);
        override_int(height, "height", 16384, &s.options.height);
        override_int(samples_per_pixel, "samples_per_pixel", 1 << 20,
                     &s.options.samples_per_pixel);
        if (!CheckRenderSize(s.options.width, s.options.height, s.options.samples_per_pixel,
                             &error)) {
          throw Error("width, height, samples_per_pixel (or the settings): " + error);
        }
        std::shared_ptr<const Body> body;
        double e = 0.0;
        std::uint64_t orientation_seed = 1;
        if (style) {
          body = style->style.body;
          e = HairTypeEccentricity(style->style.hair_type);
          orientation_seed = style->style.seed;
        }
        if (!body_arg.is_none()) body = BodyFrom(body_arg);
        if (eccentricity) e = *eccentricity;
        CheckThreads(threads);
        RenderScene scene;
        if (!MakeRenderScene(s, curves, body, e, orientation_seed, &scene, &error)) {
          throw Error("render: " + error);
        }
        Image image;
        RenderStats stats;
        bool ok = false;
        std::atomic<bool> cancel{false};
        RenderOptions options = s.options;
        options.threads = static_cast<int>(threads);
        options.cancel = &cancel;
        RunInterruptibly([&] { ok = Render(scene, options, &image, &stats, &error); }, &cancel);
        if (!ok) throw Error("render: " + error);
        py::object result;
        if (srgb) {
          std::vector<unsigned char> codes = EncodeSrgb8(image, s.exposure);
          result = OwnedArray(std::move(codes), {image.height, image.width, 3});
        } else {
          result = ImageArray(std::move(image));
        }
        if (return_stats) return py::object(py::make_tuple(result, stats));
        return result;
      },
      py::arg("hair") = py::none(), py::arg("hairstyle") = py::none(),
      py::arg("settings") = py::none(), py::arg("body") = py::none(),
      py::arg("width") = py::none(), py::arg("height") = py::none(),
      py::arg("samples_per_pixel") = py::none(), py::arg("eccentricity") = py::none(),
      py::arg("threads") = 0, py::arg("srgb") = false, py::arg("return_stats") = false,
      "Path traces hair and body (render.h) as `ringlet render` does. hair: HairCurves or a "
      "Groom (which brings its hairstyle). hairstyle (Hairstyle, dict or path): its body, "
      "fibre eccentricity, seed and \"render\" settings. settings: a \"render\" object dict "
      "(docs/hairstyle-format.md) replacing the hairstyle's. body: a ringlet.Body, a body file "
      "path or a body dict (replacing the hairstyle's). width, height (pixels), "
      "samples_per_pixel override the settings; "
      "eccentricity in [0, 1) overrides the hairstyle's (default 0). threads: 0 = all cores "
      "(the image does not depend on it). Returns an (H, W, 3) float32 array of linear "
      "radiance (W sr^-1 m^-2 per channel, row 0 at the top), or with srgb=True the uint8 sRGB "
      "codes that `ringlet render` writes to its PNG (exposure applied, clamped); with "
      "return_stats=True a tuple (image, RenderStats). Releases the GIL; Ctrl-C stops it.");
  m.def(
      "encode_srgb8",
      [](const py::handle& image, double exposure) {
        RequireNumber(exposure >= 0.0, exposure, "exposure", "a finite number >= 0");
        const Image im = ImageFrom(image);
        std::vector<unsigned char> codes = EncodeSrgb8(im, exposure);
        return OwnedArray(std::move(codes), {im.height, im.width, 3});
      },
      py::arg("image"), py::arg("exposure") = 1.0,
      "Linear (H, W, 3) radiance -> the uint8 sRGB codes of its PNG (times exposure, clamped "
      "to [0, 1], IEC 61966-2-1).");
  m.def(
      "write_png",
      [](const std::string& path, const py::handle& image, double exposure, bool overwrite) {
        std::string error;
        if (!WritePng(path, ImageFrom(image), exposure, overwrite, &error)) throw Error(error);
      },
      py::arg("path"), py::arg("image"), py::arg("exposure") = 1.0, py::arg("overwrite") = false,
      "Writes linear (H, W, 3) radiance as an 8-bit sRGB PNG, atomically (png_image.h).");
}

}  // namespace ringlet::python
