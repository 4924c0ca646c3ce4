// The text mutator of the fuzzers (scripts/fuzz: mybot_gazebo_lite's fuzz_loaders, mybot_nav_bringup's
// fuzz_nav): mutations where a hand edit or a broken generator would make them. A number becomes
// nan, -1, 0, 1e308 or another special value; an attribute value or element text takes another
// one's; a line is lost, doubled or moved; the text is cut short; a byte flips. Structured
// mutations find more than byte flips: the parsers reject most noise at once. Header-only, no ROS;
// for the fuzzers, not for the products.
#pragma once

#include <fstream>
#include <iterator>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace mybot_common
{
namespace fuzz
{
inline const char* const kSpecials[] = {"nan",    "inf",        "-inf", "-1", "0",   "1e308",      "-1e308",
                                        "1e-310", "1e9",        "-0",   "x",  "",    "1 2",        "0 0 0",
                                        "1e400",  "4294967296", "1e-9", "2",  "0.5", "3.14159265", "100000"};

inline std::string slurp(const std::string& path)
{
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

inline void spit(const std::string& path, const std::string& text)
{
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f << text;
}

inline std::vector<std::string> splitLines(const std::string& s)
{
  std::vector<std::string> lines;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);)
    lines.push_back(l);
  return lines;
}

inline std::string joinLines(const std::vector<std::string>& lines)
{
  std::string s;
  for (const auto& l : lines)
    s += l + "\n";
  return s;
}

// Every match of `re` in `s` as (position, length).
inline std::vector<std::pair<size_t, size_t>> matches(const std::string& s, const std::regex& re)
{
  std::vector<std::pair<size_t, size_t>> out;
  for (auto it = std::sregex_iterator(s.begin(), s.end(), re); it != std::sregex_iterator(); ++it)
    out.emplace_back(it->position(), it->length());
  return out;
}

class Mutator
{
public:
  explicit Mutator(unsigned seed) : rng_(seed) {}

  std::string mutate(std::string s)
  {
    const int n = 1 + pick(4);
    for (int i = 0; i < n && !s.empty(); ++i)
      s = once(s);
    return s;
  }

private:
  size_t pick(size_t n) { return n == 0 ? 0 : std::uniform_int_distribution<size_t>(0, n - 1)(rng_); }

  std::string once(const std::string& s)
  {
    static const std::regex number(R"(-?[0-9]*\.?[0-9]+([eE][-+]?[0-9]+)?)");
    static const std::regex quoted(R"("[^"<>]*")");
    static const std::regex text(R"(>[^<>]+<)");
    switch (pick(8))
    {
      case 0:
      case 1:  // a number becomes a special value
      {
        const auto m = matches(s, number);
        if (m.empty())
          return s;
        const auto [at, len] = m[pick(m.size())];
        return s.substr(0, at) + kSpecials[pick(std::size(kSpecials))] + s.substr(at + len);
      }
      case 2:  // an attribute value or element text takes another one's
      {
        const auto m = matches(s, pick(2) ? quoted : text);
        if (m.size() < 2)
          return s;
        const auto [at, len] = m[pick(m.size())];
        const auto [from, from_len] = m[pick(m.size())];
        return s.substr(0, at) + s.substr(from, from_len) + s.substr(at + len);
      }
      case 3:  // a line lost
      {
        auto lines = splitLines(s);
        lines.erase(lines.begin() + pick(lines.size()));
        return joinLines(lines);
      }
      case 4:  // a line doubled
      {
        auto lines = splitLines(s);
        const size_t i = pick(lines.size());
        lines.insert(lines.begin() + pick(lines.size()), lines[i]);
        return joinLines(lines);
      }
      case 5:  // a line moved
      {
        auto lines = splitLines(s);
        std::swap(lines[pick(lines.size())], lines[pick(lines.size())]);
        return joinLines(lines);
      }
      case 6:  // cut short
        return s.substr(0, pick(s.size()));
      default:  // a byte flips
      {
        std::string t = s;
        t[pick(t.size())] ^= static_cast<char>(1 << pick(8));
        return t;
      }
    }
  }

  std::mt19937 rng_;
};

}  // namespace fuzz
}  // namespace mybot_common
