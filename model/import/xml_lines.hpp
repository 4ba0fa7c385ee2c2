/// \file
/// Where elements of a model file are (tinyxml2's line numbers), so that the
/// importers' messages can say "joint 'knee' (line 42)": the model libraries
/// (MuJoCo's compiler, urdfdom) do not report lines. Also the first error of
/// a broken file, with its line.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace tinyxml2 {
class XMLElement;
}

namespace lieflow {
namespace model_import {

class XmlLines {
 public:
  /// Parses `text` (throws InvalidInput naming `path`, the line and
  /// tinyxml2's reason when it is not well-formed XML).
  XmlLines(const std::string& text, const std::string& path);
  ~XmlLines();
  XmlLines(const XmlLines&) = delete;
  XmlLines& operator=(const XmlLines&) = delete;

  /// The line of the first element <tag name="NAME">, or 0.
  int line(const std::string& tag, const std::string& name) const;
  /// The line of the first element <tag>, or 0.
  int firstLine(const std::string& tag) const;

  /// Every element (depth first, document order); see tinyxml2::XMLElement.
  const std::vector<const tinyxml2::XMLElement*>& elements() const { return elements_; }
  /// The root element's tag ("robot", "mujoco").
  std::string rootTag() const;

  /// Checks every number the file holds where it is written: each attribute
  /// whose value is a list of numbers (every whitespace-separated token reads
  /// whole as a number, "nan" and "1e400" included), except those named in
  /// `text_attributes` (names and references, which may look like numbers),
  /// must hold finite numbers within ±kMaxInputMagnitude
  /// (liegroup/input_number.hpp). Throws InvalidInput naming `path`, the
  /// element (its name and line) and the attribute.
  void requireUsableNumbers(const std::string& path, const std::vector<std::string>& text_attributes) const;

  /// "geom 'arm' (line 12)", or "geom (line 12)" for an unnamed element.
  static std::string label(const tinyxml2::XMLElement* e);

 private:
  struct Document;
  Document* doc_;
  std::vector<const tinyxml2::XMLElement*> elements_;
  std::map<std::string, int> lines_;  ///< "tag\nname" → line
};

}  // namespace model_import
}  // namespace lieflow
