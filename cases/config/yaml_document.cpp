#include "cases/config/yaml_document.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <limits>
#include <sstream>

#include <yaml-cpp/eventhandler.h>

namespace radnet::cases {
namespace {

// Where the text's YAML documents start, the first three at most, from the parser's events
// alone. Not YAML::LoadAll: yaml-cpp 0.7 never ends it on a flow indicator where a block
// value should start (a line opening with ','): it returns empty documents at the same mark
// for ever (a fuzzed case file took 24 GB in 26 s). Two starts at one mark are that.
class DocumentStarts : public YAML::EventHandler {
 public:
  std::vector<YAML::Mark> marks;
  void OnDocumentStart(const YAML::Mark& mark) override { marks.push_back(mark); }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
};

std::vector<YAML::Mark> documentStarts(const std::string& text) {
  std::istringstream in(text);
  YAML::Parser parser(in);
  DocumentStarts starts;
  for (int k = 0; k < 3 && parser.HandleNextDocument(starts); ++k) {
  }
  return starts.marks;
}

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

const char* kindName(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Null: return "nothing (null)";
    case YAML::NodeType::Scalar: return "a scalar";
    case YAML::NodeType::Sequence: return "a sequence";
    case YAML::NodeType::Map: return "a mapping";
    default: return "nothing";
  }
}

}  // namespace

std::optional<std::string> nearestWord(const std::string& word, const std::vector<std::string>& allowed) {
  std::optional<std::string> best;
  size_t best_d = std::max<size_t>(2, word.size() / 3) + 1;  // only plausible typos
  for (const auto& candidate : allowed) {
    const size_t d = editDistance(word, candidate);
    if (d < best_d) {
      best_d = d;
      best = candidate;
    }
  }
  return best;
}

std::optional<std::string> nearestWord(const std::string& word, std::initializer_list<const char*> allowed) {
  return nearestWord(word, std::vector<std::string>(allowed.begin(), allowed.end()));
}

YamlDocument YamlDocument::load(const std::string& path) {
  // Only regular files: a FIFO would block forever and /dev/zero would be read without end.
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw InputError(path, 0, 0, "not a regular file (a FIFO, device or directory cannot be a case or an include)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, 0, "cannot open the file for reading");
  std::ostringstream buf;
  buf << in.rdbuf();
  return parse(buf.str(), path);
}

namespace {

// YAML lets a mapping name a key twice and keeps one silently; a case file must not. Walks
// the document (at most kMaxVisits nodes, so that nested aliases cannot expand without end).
constexpr long kMaxVisits = 2000000;

void checkDuplicateKeys(const YAML::Node& node, const std::string& label, long& visits) {
  if (++visits > kMaxVisits)
    throw InputError(label, node.Mark().line + 1, node.Mark().column + 1,
                     "the document expands to more than 2e6 nodes (aliases nested too deep?)");
  if (node.IsMap()) {
    std::map<std::string, YAML::Mark> seen;
    for (const auto& kv : node) {
      if (kv.first.IsScalar()) {
        const auto [it, fresh] = seen.emplace(kv.first.Scalar(), kv.first.Mark());
        if (!fresh)
          throw InputError(label, kv.first.Mark().line + 1, kv.first.Mark().column + 1,
                           "duplicate key '" + kv.first.Scalar() + "' (first at line " +
                               std::to_string(it->second.line + 1) + "); a key may appear once in a mapping");
      }
      checkDuplicateKeys(kv.second, label, visits);
    }
  } else if (node.IsSequence()) {
    for (const auto& child : node) checkDuplicateKeys(child, label, visits);
  }
}

}  // namespace

YamlDocument YamlDocument::parse(const std::string& text, const std::string& label) {
  try {
    const std::vector<YAML::Mark> starts = documentStarts(text);
    if (starts.size() > 1 && starts[1].pos == starts[0].pos) {
      const char c = starts[1].pos < static_cast<int>(text.size()) ? text[static_cast<size_t>(starts[1].pos)] : ' ';
      throw InputError(label, starts[1].line + 1, starts[1].column + 1,
                       std::string("YAML syntax error: '") + c + "' cannot begin a value here (quote the text)");
    }
    if (starts.size() > 1)
      throw InputError(label, starts[1].line + 1, starts[1].column + 1,
                       "a second YAML document ('---'); a case file holds one");
    YAML::Node root = YAML::Load(text);
    long visits = 0;
    checkDuplicateKeys(root, label, visits);
    return YamlDocument(root, label, text);
  } catch (const YAML::ParserException& e) {
    throw InputError(label, e.mark.line + 1, e.mark.column + 1, "YAML syntax error: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw InputError(label, e.mark.line + 1, e.mark.column + 1, std::string("YAML error: ") + e.msg);
  }
}

InputError YamlDocument::error(const YAML::Node& node, const std::string& message) const {
  const YAML::Mark mark = node.IsDefined() ? node.Mark() : YAML::Mark::null_mark();
  const int line = mark.line >= 0 ? mark.line + 1 : 0;
  const int column = mark.column >= 0 ? mark.column + 1 : 0;
  return InputError(file_, line, column, message);
}

void YamlDocument::expectMap(const YAML::Node& node, const std::string& what,
                             std::initializer_list<const char*> allowed) const {
  expectMap(node, what, std::vector<std::string>(allowed.begin(), allowed.end()));
}

void YamlDocument::expectMap(const YAML::Node& node, const std::string& what,
                             const std::vector<std::string>& allowed) const {
  if (!node.IsMap()) throw error(node, what + ": expected a mapping of keys, found " + kindName(node));
  for (const auto& kv : node) {
    if (!kv.first.IsScalar()) throw error(kv.first, what + ": keys must be plain words");
    const std::string key = kv.first.Scalar();
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string msg = what + ": unknown key '" + key + "'";
      if (auto near = nearestWord(key, allowed)) msg += " (did you mean '" + *near + "'?)";
      msg += "; expected one of:";
      for (const auto& a : allowed) msg += " " + a;
      throw error(kv.first, msg);
    }
  }
}

void YamlDocument::expectSequence(const YAML::Node& node, const std::string& what) const {
  if (!node.IsSequence()) throw error(node, what + ": expected a sequence, found " + kindName(node));
}

YAML::Node YamlDocument::required(const YAML::Node& map, const std::string& key, const std::string& what) const {
  YAML::Node child = map[key];
  if (!child.IsDefined() || child.IsNull()) throw error(map, what + ": missing required key '" + key + "'");
  return child;
}

double YamlDocument::number(const YAML::Node& node, const std::string& what, double lo, double hi) const {
  double value = 0.0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, value))
    throw error(node, what + ": expected a number, found " +
                          (node.IsScalar() ? "'" + node.Scalar() + "'" : std::string(kindName(node))));
  if (!std::isfinite(value)) throw error(node, what + ": expected a finite number, found '" + node.Scalar() + "'");
  if (value < lo || value > hi) {
    std::ostringstream s;
    s << what << ": " << value << " is out of range; expected ";
    // Bounds at the ends of double's range read as open-ended ranges, not as 1.8e308.
    const double big = std::numeric_limits<double>::max();
    if (lo == std::numeric_limits<double>::min() && hi == big)
      s << "a value > 0";
    else if (hi == big)
      s << "a value >= " << lo;
    else if (lo == -big)
      s << "a value <= " << hi;
    else
      s << "a value in [" << lo << ", " << hi << "]";
    throw error(node, s.str());
  }
  return value;
}

long long YamlDocument::integer(const YAML::Node& node, const std::string& what, long long lo, long long hi) const {
  long long value = 0;
  if (!node.IsScalar() || !YAML::convert<long long>::decode(node, value))
    throw error(node, what + ": expected a whole number, found " +
                          (node.IsScalar() ? "'" + node.Scalar() + "'" : std::string(kindName(node))));
  if (value < lo || value > hi)
    throw error(node, what + ": " + std::to_string(value) + " is out of range; expected a whole number in [" +
                          std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return value;
}

namespace {

// Well-formed UTF-8 without control characters: names go into UTF-8 HDF5 strings, and a
// NUL would make two different names one in every C API downstream.
bool isCleanUtf8(const std::string& text) {
  const auto* p = reinterpret_cast<const unsigned char*>(text.data());
  const auto* end = p + text.size();
  while (p < end) {
    const unsigned char c = *p;
    int extra = 0;
    unsigned cp = 0;
    if (c < 0x80) {
      if ((c < 0x20 && c != '\t' && c != '\n' && c != '\r') || c == 0x7f) return false;  // NUL, ESC, …
      ++p;
      continue;
    }
    if ((c & 0xe0) == 0xc0) extra = 1, cp = c & 0x1f;
    else if ((c & 0xf0) == 0xe0) extra = 2, cp = c & 0x0f;
    else if ((c & 0xf8) == 0xf0) extra = 3, cp = c & 0x07;
    else return false;
    if (end - p <= extra) return false;
    for (int k = 1; k <= extra; ++k) {
      if ((p[k] & 0xc0) != 0x80) return false;
      cp = (cp << 6) | (p[k] & 0x3f);
    }
    static constexpr unsigned kMin[4] = {0, 0x80, 0x800, 0x10000};
    if (cp < kMin[extra] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return false;  // overlong, surrogate
    p += extra + 1;
  }
  return true;
}

}  // namespace

std::string YamlDocument::string(const YAML::Node& node, const std::string& what) const {
  if (!node.IsScalar() || node.Scalar().empty())
    throw error(node, what + ": expected a non-empty text, found " + kindName(node));
  if (!isCleanUtf8(node.Scalar()))
    throw error(node, what + ": the text holds a control character (NUL, ESC, …) or is not valid UTF-8");
  return node.Scalar();
}

bool YamlDocument::boolean(const YAML::Node& node, const std::string& what) const {
  bool value = false;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value))
    throw error(node, what + ": expected true or false");
  return value;
}

Eigen::Vector3d YamlDocument::vector3(const YAML::Node& node, const std::string& what, bool nonzero) const {
  constexpr double kBig = std::numeric_limits<double>::max();
  if (!node.IsSequence() || node.size() != 3) throw error(node, what + ": expected [x, y, z]");
  const Eigen::Vector3d v(number(node[0], what + "[0]", -kBig, kBig), number(node[1], what + "[1]", -kBig, kBig),
                          number(node[2], what + "[2]", -kBig, kBig));
  if (nonzero && !(v.norm() > 0)) throw error(node, what + ": expected a non-zero vector");
  return v;
}

int YamlDocument::nodeIndex(const YAML::Node& node, const std::string& what,
                            const std::vector<std::string>& names) const {
  const std::string name = string(node, what);
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) {
    std::string msg = what + ": no node named '" + name + "'";
    if (auto near = nearestWord(name, names)) msg += " (did you mean '" + *near + "'?)";
    throw error(node, msg);
  }
  return static_cast<int>(it - names.begin());
}

std::string YamlDocument::choice(const YAML::Node& node, const std::string& what,
                                 const std::vector<std::string>& choices) const {
  const std::string word = string(node, what);
  if (std::find(choices.begin(), choices.end(), word) != choices.end()) return word;
  std::string msg = what + ": '" + word + "'";
  if (auto near = nearestWord(word, choices)) msg += " (did you mean '" + *near + "'?)";
  msg += "; expected ";
  for (size_t k = 0; k < choices.size(); ++k)
    msg += (k == 0 ? "" : k + 1 == choices.size() ? " or " : ", ") + choices[k];
  throw error(node, msg);
}

}  // namespace radnet::cases
