// Strict JSON parsing (see json_strict.h). The SAX handler forwards every event to nlohmann's own DOM
// builder and keeps a stack of the containers it is in, for duplicate keys and for the key path.
#include <hr/json_strict.h>

#include <hr/echo.h>
#include <hr/limits.h>
#include <hr/types.h>

#include <algorithm>
#include <set>
#include <vector>

namespace hr {
namespace {

using json = nlohmann::json;

class StrictSax {
 public:
  StrictSax(json& root, const std::string& text, const std::string& file) : dom_(root, false), text_(text), file_(file) {}

  bool null() { return value(), dom_.null(); }
  bool boolean(bool v) { return value(), dom_.boolean(v); }
  bool number_integer(json::number_integer_t v) { return value(), dom_.number_integer(v); }
  bool number_unsigned(json::number_unsigned_t v) { return value(), dom_.number_unsigned(v); }
  bool number_float(json::number_float_t v, const std::string& s) { return value(), dom_.number_float(v, s); }
  bool string(std::string& v) { return value(), dom_.string(v); }
  bool binary(json::binary_t& v) { return value(), dom_.binary(v); }
  bool start_object(std::size_t n) { return enter(false), dom_.start_object(n); }
  bool end_object() { return leave(), dom_.end_object(); }
  bool start_array(std::size_t n) { return enter(true), dom_.start_array(n); }
  bool end_array() { return leave(), dom_.end_array(); }
  bool key(std::string& k) {
    Frame& f = stack_.back();
    if (!f.keys.insert(k).second) {
      std::string where = path(stack_.size() - 1);
      where += (where.empty() ? "" : ".") + k.substr(0, limits::kMaxEcho);
      throw InputError(file_ + ": " + where + ": duplicate key " + echo(k) +
                       " (refused: one of the two values would be silently lost)");
    }
    f.key = k;
    return dom_.key(k);
  }
  bool parse_error(std::size_t position, const std::string& /*token*/, const nlohmann::detail::exception& ex) {
    std::size_t at = std::min(position, text_.size());
    std::size_t line = 1 + static_cast<std::size_t>(std::count(text_.begin(), text_.begin() + std::ptrdiff_t(at), '\n'));
    std::string what = ex.what();
    if (ex.id == 406) what = "number out of range (finite double precision numbers only): " + what;
    throw InputError(file_ + ": line " + std::to_string(line) + ": malformed JSON: " + clipMessage(what, 300));
  }

 private:
  struct Frame {
    bool array = false;
    std::size_t index = 0;
    std::string key;
    std::set<std::string> keys;
  };
  void value() {
    if (!stack_.empty() && stack_.back().array) ++stack_.back().index;
  }
  void enter(bool array) {
    if (stack_.size() >= std::size_t(limits::kMaxJsonDepth))
    {
      std::string where = path(stack_.size());
      throw InputError(file_ + ": " + (where.empty() ? "(top level)" : where) + ": nested deeper than " +
                       std::to_string(limits::kMaxJsonDepth) + " levels");
    }
    stack_.push_back({array, 0, {}, {}});
  }
  void leave() {
    stack_.pop_back();
    value();
  }
  /// The key path through the first `frames` containers ("objects[2].transform"); each contributes
  /// the key or index under which the next value sits.
  std::string path(std::size_t frames) const {
    std::string p;
    for (std::size_t i = 0; i < frames && i < stack_.size(); ++i) {
      const Frame& f = stack_[i];
      // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) about "[" + to_string(...) here.
      if (f.array) {
        p.append("[").append(std::to_string(f.index)).append("]");
      } else {
        if (!p.empty()) p.append(".");
        p.append(f.key, 0, limits::kMaxEcho);
      }
    }
    return p;
  }

  nlohmann::detail::json_sax_dom_parser<json> dom_;
  const std::string& text_;
  const std::string& file_;
  std::vector<Frame> stack_;
};

}  // namespace

json parseStrictJson(const std::string& text, const std::string& file) {
  json root;
  StrictSax sax(root, text, file);
  json::sax_parse(text, &sax);
  return root;
}

}  // namespace hr
