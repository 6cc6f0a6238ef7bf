#pragma once
// Reading YAML with positions: every error names file:line:column and what was expected.
#include "cases/config/errors.hpp"

#include <Eigen/Dense>

#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

namespace radnet::cases {

/// A YAML document with the name of the file it came from.
class YamlDocument {
 public:
  /// Parses a file. @throws InputError (unreadable file or YAML syntax error, with position)
  static YamlDocument load(const std::string& path);
  /// Parses text (for tests); `label` stands for the file name in messages.
  static YamlDocument parse(const std::string& text, const std::string& label);

  const YAML::Node& root() const { return root_; }
  const std::string& file() const { return file_; }
  const std::string& text() const { return text_; }

  /// An InputError located at `node` (1-based line/column).
  [[nodiscard]] InputError error(const YAML::Node& node, const std::string& message) const;
  /// "FILE:LINE:COLUMN: message", for a warning about what `node` holds.
  std::string located(const YAML::Node& node, const std::string& message) const { return error(node, message).what(); }

  /// Requires a mapping and rejects keys outside `allowed`, suggesting the nearest one.
  void expectMap(const YAML::Node& node, const std::string& what, std::initializer_list<const char*> allowed) const;
  void expectMap(const YAML::Node& node, const std::string& what, const std::vector<std::string>& allowed) const;
  void expectSequence(const YAML::Node& node, const std::string& what) const;

  /// The child `key` of a mapping, required. @throws InputError at the mapping
  YAML::Node required(const YAML::Node& map, const std::string& key, const std::string& what) const;

  /// A finite number in [lo, hi] (NaN and infinities rejected).
  double number(const YAML::Node& node, const std::string& what, double lo, double hi) const;
  /// An integer in [lo, hi].
  long long integer(const YAML::Node& node, const std::string& what, long long lo, long long hi) const;
  std::string string(const YAML::Node& node, const std::string& what) const;
  bool boolean(const YAML::Node& node, const std::string& what) const;
  /// [x, y, z], finite; with `nonzero`, the zero vector is refused.
  Eigen::Vector3d vector3(const YAML::Node& node, const std::string& what, bool nonzero = false) const;
  /// The index of the node named by `node` in `names`, with a did-you-mean when not found.
  int nodeIndex(const YAML::Node& node, const std::string& what, const std::vector<std::string>& names) const;
  /// One word of `choices` (listed in the message when the word is not one of them).
  std::string choice(const YAML::Node& node, const std::string& what, const std::vector<std::string>& choices) const;

 private:
  YamlDocument(YAML::Node root, std::string file, std::string text)
      : root_(std::move(root)), file_(std::move(file)), text_(std::move(text)) {}
  YAML::Node root_;
  std::string file_;
  std::string text_;
};

/// The allowed word nearest to `word` by edit distance, if it is plausibly a typo.
std::optional<std::string> nearestWord(const std::string& word, const std::vector<std::string>& allowed);
std::optional<std::string> nearestWord(const std::string& word, std::initializer_list<const char*> allowed);

}  // namespace radnet::cases
