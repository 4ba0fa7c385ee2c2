// Only with a model reader (they bring tinyxml2, joints/CMakeLists.txt).
#if defined(LIEFLOW_HAVE_MUJOCO) || defined(LIEFLOW_HAVE_URDFDOM)
#include "joints/import/xml_lines.hpp"

#include <tinyxml2.h>

#include "liegroup/invalid_input.hpp"

namespace lieflow {
namespace model_import {

struct XmlLines::Document {
  tinyxml2::XMLDocument xml;
};

XmlLines::XmlLines(const std::string& text, const std::string& path) : doc_(new Document) {
  if (doc_->xml.Parse(text.c_str(), text.size()) != tinyxml2::XML_SUCCESS) {
    const std::string where = path + ": line " + std::to_string(doc_->xml.ErrorLineNum());
    const std::string why = std::string("broken XML: ") + doc_->xml.ErrorStr();
    delete doc_;
    doc_ = nullptr;
    throw InvalidInput(where, why);
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

std::string XmlLines::rootTag() const {
  const tinyxml2::XMLElement* root = doc_->xml.RootElement();
  return root ? root->Name() : "";
}

}  // namespace model_import
}  // namespace lieflow

#endif
