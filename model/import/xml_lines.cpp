// Only with a model reader (they bring tinyxml2, model/CMakeLists.txt).
#if defined(LIEFLOW_HAVE_MUJOCO) || defined(LIEFLOW_HAVE_URDFDOM)
#include "model/import/xml_lines.hpp"

#include <tinyxml2.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <sstream>

#include "liegroup/input_number.hpp"
#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace model_import {

struct XmlLines::Document {
  tinyxml2::XMLDocument xml;
};

namespace {

/// tinyxml2's error, in words (its ErrorStr() names its enum: "Error=
/// XML_ELEMENT_DEPTH_EXCEEDED ErrorID=18 (0x12) Line number=1000").
std::string xmlProblem(tinyxml2::XMLError e) {
  switch (e) {
    case tinyxml2::XML_ERROR_EMPTY_DOCUMENT: return "the file holds no XML element (it is empty)";
    case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT: return "an element is closed by another element's end tag";
    case tinyxml2::XML_ERROR_PARSING_ELEMENT: return "a broken element (a tag that is not closed or not well formed)";
    case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE: return "a broken attribute (name=\"value\" expected)";
    case tinyxml2::XML_ERROR_PARSING_TEXT: return "broken text between elements";
    case tinyxml2::XML_ERROR_PARSING_CDATA: return "a broken CDATA section";
    case tinyxml2::XML_ERROR_PARSING_COMMENT: return "a comment that is not closed (<!-- ... -->)";
    case tinyxml2::XML_ERROR_PARSING_DECLARATION: return "a broken declaration (<?xml ... ?>)";
    case tinyxml2::XML_ERROR_PARSING_UNKNOWN: return "an unknown construct (<! ... >)";
    case tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED:
      return "elements nested deeper than " + std::to_string(TINYXML2_MAX_ELEMENT_DEPTH) +
             " levels (the XML reader's limit)";
    default: return "not well-formed XML";
  }
}

}  // namespace

XmlLines::XmlLines(const std::string& text, const std::string& path) : doc_(new Document) {
  const tinyxml2::XMLError error = doc_->xml.Parse(text.c_str(), text.size());
  if (error != tinyxml2::XML_SUCCESS) {
    const int line = doc_->xml.ErrorLineNum();
    const std::string where = line > 0 ? path + ": line " + std::to_string(line) : path;
    delete doc_;
    doc_ = nullptr;
    throw InvalidInput(where, "broken XML: " + xmlProblem(error));
  }
  std::vector<const tinyxml2::XMLElement*> stack;
  if (const tinyxml2::XMLElement* root = doc_->xml.RootElement()) stack.push_back(root);
  while (!stack.empty()) {
    const tinyxml2::XMLElement* e = stack.back();
    stack.pop_back();
    elements_.push_back(e);
    if (const char* name = e->Attribute("name")) lines_.emplace(std::string(e->Name()) + "\n" + name, e->GetLineNum());
    std::vector<const tinyxml2::XMLElement*> children;
    for (const tinyxml2::XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) children.push_back(c);
    stack.insert(stack.end(), children.rbegin(), children.rend());
  }
}

XmlLines::~XmlLines() { delete doc_; }

int XmlLines::line(const std::string& tag, const std::string& name) const {
  const auto it = lines_.find(tag + "\n" + name);
  return it == lines_.end() ? 0 : it->second;
}

int XmlLines::firstLine(const std::string& tag) const {
  for (const tinyxml2::XMLElement* e : elements_)
    if (tag == e->Name()) return e->GetLineNum();
  return 0;
}

std::string XmlLines::rootTag() const {
  const tinyxml2::XMLElement* root = doc_->xml.RootElement();
  return root ? root->Name() : "";
}

std::string XmlLines::label(const tinyxml2::XMLElement* e) {
  std::string s = e->Name();
  if (const char* name = e->Attribute("name")) s += " '" + std::string(name) + "'";
  return s + " (line " + std::to_string(e->GetLineNum()) + ")";
}

namespace {

/// The value of a token that reads whole as a number (strtod: decimal, hex,
/// "nan", "inf"; a decimal beyond double range reads as ±inf), or false.
bool readsAsNumber(const std::string& token, double* value) {
  if (token.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(token.c_str(), &end);
  if (end != token.c_str() + token.size()) return false;
  *value = v;
  return true;
}

}  // namespace

void XmlLines::requireUsableNumbers(const std::string& path, const std::vector<std::string>& text_attributes) const {
  for (const tinyxml2::XMLElement* e : elements_) {
    for (const tinyxml2::XMLAttribute* a = e->FirstAttribute(); a; a = a->Next()) {
      const std::string name = a->Name();
      if (std::find(text_attributes.begin(), text_attributes.end(), name) != text_attributes.end()) continue;
      std::istringstream tokens(a->Value());
      std::vector<std::pair<std::string, double>> numbers;
      std::string token;
      bool all_numbers = true;
      while (all_numbers && tokens >> token) {
        double v = 0.0;
        all_numbers = readsAsNumber(token, &v);
        numbers.emplace_back(token, v);
      }
      if (!all_numbers) continue;
      for (const auto& [text, v] : numbers) {
        std::string problem = inputNumberProblem(v);
        if (problem.empty()) continue;
        if (std::isinf(v) && text.find_first_of("iI") == std::string::npos)
          problem = "'" + text + "' overflows a double";
        throw InvalidInput(path + ": " + label(e) + ", attribute " + name, problem);
      }
    }
  }
}

}  // namespace model_import
}  // namespace lieflow

#endif
