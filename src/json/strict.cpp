#include "json/strict.hpp"

#include <vector>

#include "uavcover/error.hpp"

namespace uavcover::strict {

namespace {

using nlohmann::json;

// A key as shown in a message: control characters replaced, long keys shortened.
std::string printable(const std::string& key) {
  constexpr std::size_t kMax = 40;
  std::string out;
  for (char c : key.substr(0, kMax)) out += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? '?' : c;
  if (key.size() > kMax) out += "...";
  return out;
}

// Builds the document from SAX events (like nlohmann's DOM parser) while bounding the depth and
// refusing duplicate keys. Errors are thrown as InputError and leave through sax_parse.
class Builder {
 public:
  Builder(json& root, const std::string& what, std::size_t max_depth)
      : root_(root), what_(what), max_depth_(max_depth) {}

  bool null() { return value(nullptr); }
  bool boolean(bool v) { return value(v); }
  bool number_integer(json::number_integer_t v) { return value(v); }
  bool number_unsigned(json::number_unsigned_t v) { return value(v); }
  bool number_float(json::number_float_t v, const json::string_t&) { return value(v); }
  bool string(json::string_t& v) { return value(std::move(v)); }
  bool binary(json::binary_t& v) { return value(std::move(v)); }

  bool start_object(std::size_t) { return open(json::value_t::object); }
  bool start_array(std::size_t) { return open(json::value_t::array); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool key(json::string_t& k) {
    Frame& top = stack_.back();
    if (top.node->contains(k)) {
      top.key = k;
      throw InputError(path(), "duplicate key \"" + printable(k) + "\" in " + what_ +
                                   " (each key may appear once in an object)");
    }
    top.key = k;
    top.pending = &(*top.node)[k];
    return true;
  }

  template <class Exception>
  bool parse_error(std::size_t, const std::string&, const Exception& e) {
    // "[json.exception.parse_error.101] parse error at line 1, column 9: ..." -> drop the prefix
    const std::string m = e.what();
    const auto pos = m.find("] ");
    throw InputError(what_, "malformed JSON: " + (pos == std::string::npos ? m : m.substr(pos + 2)));
  }

 private:
  struct Frame {
    json* node;
    std::string key;          // objects: the current key
    json* pending = nullptr;  // objects: the member the next value fills
  };

  // The slot the next value goes into.
  json* slot() {
    if (stack_.empty()) return &root_;
    Frame& top = stack_.back();
    if (top.node->is_array()) {
      top.node->push_back(nullptr);
      return &top.node->back();
    }
    json* p = top.pending;
    top.pending = nullptr;
    return p;
  }

  template <class V>
  bool value(V&& v) {
    *slot() = json(std::forward<V>(v));
    return true;
  }

  bool open(json::value_t type) {
    if (stack_.size() >= max_depth_)
      throw InputError(what_, "nested deeper than " + std::to_string(max_depth_) + " levels (at " + path() +
                                  "); uavcover's inputs need far fewer");
    json* s = slot();
    *s = json(type);
    stack_.push_back({s, {}});
    return true;
  }

  bool close() {
    stack_.pop_back();
    return true;
  }

  // JSON path of the current position, e.g. "features[3].properties.a" (shortened when long). In an
  // array on top of the stack, the position is the element about to be added.
  std::string path() const {
    std::string p;
    for (std::size_t i = 0; i < stack_.size(); ++i) {
      if (p.size() > 200) return p + "...";
      const json& n = *stack_[i].node;
      if (n.is_array())
        p += "[" + std::to_string(i + 1 < stack_.size() ? n.size() - 1 : n.size()) + "]";
      else
        p += (p.empty() ? "" : ".") + printable(stack_[i].key);
    }
    return p.empty() ? what_ : p;
  }

  json& root_;
  const std::string& what_;
  std::size_t max_depth_;
  std::vector<Frame> stack_;
};

}  // namespace

json parse_json(std::string_view text, const std::string& what, const JsonLimits& limits) {
  if (limits.max_bytes != 0 && text.size() > limits.max_bytes)
    throw InputError(what, "is " + std::to_string(text.size()) + " bytes, more than the limit of " +
                               std::to_string(limits.max_bytes) + " bytes");
  if (text.find_first_not_of(" \t\r\n") == std::string_view::npos)
    throw InputError(what, "is empty: expected a JSON document");
  json root;
  Builder builder(root, what, limits.max_depth == 0 ? 1 : limits.max_depth);
  json::sax_parse(text.begin(), text.end(), &builder, json::input_format_t::json, true, false);
  return root;
}

}  // namespace uavcover::strict
