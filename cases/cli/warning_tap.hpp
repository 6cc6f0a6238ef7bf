#pragma once
// The run's warnings, kept whatever -q says: every line "radnet: warning: …" written to the
// progress stream is forwarded (to stderr, or to a sink under -q) and kept, for /report/warnings
// in the result and the closing "N warnings" line (docs/design.md, "Contracts").
#include <ostream>
#include <streambuf>
#include <string>
#include <vector>

namespace radnet::cases {

class WarningTap : public std::streambuf {
 public:
  explicit WarningTap(std::ostream& target) : target_(target), stream_(this) {}
  WarningTap(const WarningTap&) = delete;
  WarningTap& operator=(const WarningTap&) = delete;

  std::ostream& stream() { return stream_; }
  /// Each warning's text without the "radnet: warning: " prefix, in the order written.
  const std::vector<std::string>& warnings() const { return warnings_; }

 protected:
  int overflow(int ch) override {
    if (ch == traits_type::eof()) return traits_type::not_eof(ch);
    target_.put(static_cast<char>(ch));
    take(static_cast<char>(ch));
    return ch;
  }
  std::streamsize xsputn(const char* text, std::streamsize count) override {
    target_.write(text, count);
    for (std::streamsize k = 0; k < count; ++k) take(text[k]);
    return count;
  }
  int sync() override {
    target_.flush();
    return 0;
  }

 private:
  void take(char ch) {
    if (ch != '\n') {
      line_ += ch;
      return;
    }
    static const std::string kPrefix = "radnet: warning: ";
    if (line_.compare(0, kPrefix.size(), kPrefix) == 0) warnings_.push_back(line_.substr(kPrefix.size()));
    line_.clear();
  }

  std::ostream& target_;
  std::ostream stream_;
  std::string line_;
  std::vector<std::string> warnings_;
};

}  // namespace radnet::cases
