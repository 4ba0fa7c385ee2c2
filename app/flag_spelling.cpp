// Library texts' `option` names as command-line flags (flag_spelling.hpp).
#include "app/flag_spelling.hpp"

namespace lieflow {
namespace app {
namespace {

bool nameStart(char c) { return c >= 'a' && c <= 'z'; }
bool nameChar(char c) { return nameStart(c) || (c >= '0' && c <= '9') || c == '_'; }

}  // namespace

std::string spellFlags(const std::string& text) {
  std::string out;
  out.reserve(text.size() + 8);
  std::size_t i = 0;
  while (i < text.size()) {
    const std::size_t open = text.find('`', i);
    if (open == std::string::npos) break;
    std::size_t end = open + 1;
    if (end < text.size() && nameStart(text[end]))
      while (end < text.size() && nameChar(text[end])) ++end;
    if (end > open + 1 && end < text.size() && text[end] == '`') {
      out.append(text, i, open - i);
      out += "--";
      for (std::size_t k = open + 1; k < end; ++k) out += text[k] == '_' ? '-' : text[k];
      i = end + 1;
    } else {
      out.append(text, i, open + 1 - i);
      i = open + 1;
    }
  }
  out.append(text, i, std::string::npos);
  return out;
}

nlohmann::ordered_json spellFlagsIn(nlohmann::ordered_json j) {
  if (j.is_string()) return spellFlags(j.get<std::string>());
  if (j.is_structured())
    for (auto& item : j) item = spellFlagsIn(std::move(item));
  return j;
}

}  // namespace app
}  // namespace lieflow
