// The text mutator of the fuzzers (scripts/fuzz: mybot_gazebo_lite's fuzz_loaders, mybot_nav_bringup's
// fuzz_nav): mutations where a hand edit or a broken generator would make them. A number becomes
// nan, -1, 0, 1e308 or another special value; an attribute value or element text takes another
// one's; a line is lost, doubled or moved; the text is cut short; a byte flips. Structured
// mutations find more than byte flips: the parsers reject most noise at once. Header-only, no ROS;
// for the fuzzers, not for the products. `drive` is their common main loop.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>
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

// One input of a fuzzer: where it came from, its text, and the folder its relative URIs are read from.
struct Input
{
  std::string path, text, dir;
};

// What became of one input: whether everything fed with it stayed finite, whether it was taken (not
// refused), and the refusal's message or what it became (printed when replaying).
struct Outcome
{
  bool finite = true, taken = true;
  std::string what;
};

// The fuzzers' driver (scripts/fuzz calls each as `FUZZER KIND SECONDS SEED OUT_DIR INPUT...`).
// SECONDS <= 0 replays each input once, unmutated, printing what became of it, and returns 1 when
// one went non-finite. Otherwise it mutates inputs (`mutate`, the Mutator's whole-text mutations
// by default) for SECONDS: each mutant stays in OUT_DIR/current.KIND while `run` has it, so that a
// crash, a sanitizer's report or a hang (20 s, SIGALRM) leaves it for scripts/fuzz to keep, and a
// non-finite one is kept as OUT_DIR/nonfinite-N.KIND (the first 50).
template <class Run, class Mutate>
int drive(const std::string& kind, double seconds, unsigned seed, const std::string& out,
          const std::vector<Input>& inputs, Run run, Mutate mutate)
{
  const std::string current = out + "/current." + kind;
  if (seconds <= 0)
  {
    int failed = 0;
    for (const Input& in : inputs)
    {
      alarm(20);
      spit(current, in.text);
      const Outcome o = run(in.text, in.dir);
      failed += o.finite ? 0 : 1;
      std::printf("%s: %s\n", in.path.c_str(), !o.finite ? "not finite" : o.what.c_str());
    }
    std::remove(current.c_str());
    std::printf("%s: %zu inputs replayed, %d non-finite\n", kind.c_str(), inputs.size(), failed);
    return failed ? 1 : 0;
  }
  Mutator mutator(seed);
  std::mt19937 pick(seed + 1);
  const auto start = std::chrono::steady_clock::now();
  long rounds = 0, taken = 0, nonfinite = 0;
  while (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < seconds)
  {
    const Input& in = inputs[std::uniform_int_distribution<size_t>(0, inputs.size() - 1)(pick)];
    const std::string mutated = mutate(in.text, mutator, pick);
    spit(current, mutated);
    alarm(20);
    const Outcome o = run(mutated, in.dir);
    if (!o.finite && nonfinite < 50)
      spit(out + "/nonfinite-" + std::to_string(nonfinite++) + "." + kind, mutated);
    taken += o.taken ? 1 : 0;
    ++rounds;
  }
  alarm(0);
  std::remove(current.c_str());
  std::printf("%s: %ld rounds (%ld taken), %ld non-finite\n", kind.c_str(), rounds, taken, nonfinite);
  return 0;
}

// The inputs named on a fuzzer's command line from argv[first] on; each one's folder is its own
// unless `dir` is given (the floor plans' fuzzing writes the image beside the YAML in OUT_DIR).
inline std::vector<Input> readInputs(int argc, char** argv, int first, const std::string& dir = "")
{
  std::vector<Input> inputs;
  for (int i = first; i < argc; ++i)
  {
    const std::string path = argv[i];
    const auto slash = path.rfind('/');
    inputs.push_back({path, slurp(path),
                      !dir.empty()                 ? dir
                      : slash == std::string::npos ? "."
                                                   : path.substr(0, slash)});
  }
  return inputs;
}

// The same, each mutant the Mutator's whole-text mutation of an input.
template <class Run>
int drive(const std::string& kind, double seconds, unsigned seed, const std::string& out,
          const std::vector<Input>& inputs, Run run)
{
  return drive(kind, seconds, seed, out, inputs, run,
               [](const std::string& text, Mutator& m, std::mt19937&) { return m.mutate(text); });
}

}  // namespace fuzz
}  // namespace mybot_common
