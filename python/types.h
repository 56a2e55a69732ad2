// Types shared between the parts of the Python module (bindings.h).
#pragma once

#include <pybind11/pybind11.h>

#include <vector>

#include <memory>
#include <string>

#include "ringlet/body.h"
#include "ringlet/hairstyle.h"
#include "ringlet/math.h"
#include "ringlet/render_json.h"
#include "ringlet/result_json.h"
#include "ringlet/scene_json.h"
#include "ringlet/styling.h"

namespace ringlet::python {

/// What ringlet.StrandResult holds: the result as `ringlet solve` writes it and the material
/// frames at its points (SampleFramedCentreline with the same points per segment).
struct SolvedStrand {
  StrandResult result;
  std::vector<Mat3> frames;
};

/// The scene of a Scene, a scene dict, a path, a StrandModel or a list of StrandModel.
Scene SceneFrom(pybind11::handle scene);

/// What ringlet.Hairstyle holds: a hairstyle file's hair, its styling operations (applied by
/// StyledHair.apply_operations, as `ringlet style` does) and its render settings (used by
/// ringlet.render, as `ringlet render` does).
struct HairstyleFile {
  Hairstyle style;
  std::vector<StyleOperation> operations;
  RenderSettings render;
  /// What it was parsed from, for pickling (the hairstyle is parsed again from them): the JSON
  /// text of the file or dict and the absolute directory of its relative paths.
  std::string document_text;
  std::string base_directory;
};

/// The hairstyle of a document text and base directory (HairstyleFile's pickle).
std::shared_ptr<const HairstyleFile> HairstyleFromText(const std::string& text,
                                                       const std::string& base_directory);

/// What ringlet.Groom holds: the groom and the hairstyle it came from.
struct GroomResult {
  std::shared_ptr<const HairstyleFile> hairstyle;
  Groom groom;
};

/// The hairstyle of a Hairstyle, a hairstyle dict (relative paths from base_directory) or a path.
std::shared_ptr<const HairstyleFile> HairstyleFrom(pybind11::handle hairstyle,
                                                   const std::string& base_directory);

/// What ringlet.Body holds: an immutable body and what it was parsed from, for pickling (the
/// body is parsed again from them): the JSON text of the body file or dict and the absolute
/// directory of its relative OBJ paths.
struct BodyFile {
  std::shared_ptr<const Body> body;
  std::string document_text;
  std::string base_directory;
};

/// The body of a document text and base directory (BodyFile's pickle). Bodies still alive in
/// this process are shared, keyed by both (a mesh body's grid takes seconds to build).
std::shared_ptr<const BodyFile> BodyFromText(const std::string& text,
                                             const std::string& base_directory);

/// A ringlet.Body for an already built body (a hairstyle's) and the document it was built from:
/// the one alive from the same text and directory, else this one (no rebuild).
std::shared_ptr<const BodyFile> AdoptBody(const std::string& text,
                                          const std::string& base_directory,
                                          std::shared_ptr<const Body> body);

/// The body of a ringlet.Body, a body file path, a body dict (relative OBJ paths from
/// base_directory) or None (null). `field` names the argument in errors ("body").
std::shared_ptr<const Body> BodyFrom(pybind11::handle body, const std::string& field = "body",
                                     const std::string& base_directory = ".");

}  // namespace ringlet::python
