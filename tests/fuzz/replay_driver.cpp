// Standalone fuzz driver (any compiler): replays corpus files through LLVMFuzzerTestOneInput, then
// runs a bounded number of seeded random mutations of them, so a short fuzz run belongs in ctest.
//
//   fuzz_iso_replay [--runs N] [--seed S] [--max-len BYTES] PATH...   (files or folders, recursively)
//
// Mutations: byte flips, inserts, deletes, block duplication, splices of two inputs, and inserts of
// G-code tokens (words, brackets, comments, O-words) so that mutants reach the interpreter and not
// only the lexer. Deterministic for a given seed and inputs; a crash or abort fails the run.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;

const char* const kTokens[] = {
    "G0 ", "G1 ", "G2 ", "G3 ", "G4 P1 ", "G17 ", "G18 ", "G19 ", "G20 ", "G21 ", "G40 ", "G41 D1 ", "G42.1 D2 ",
    "G43 H1 ", "G5 I1 J1 P1 Q1 ", "G5.2 ", "G5.3 ", "G54 ", "G61 ", "G64 P0.1 ", "G81 R1 Z-1 ", "G83 Q1 ", "G90 ",
    "G91 ", "G92 X0 ", "G10 L2 P1 X1 ", "G28 ", "M3 ", "M5 ", "M6 T1 ", "M30 ", "M66 P0 L3 Q1 ", "X1 ", "Y-2.5 ",
    "Z1e3 ", "I1 ", "J-1 ", "K1 ", "R5 ", "F100 ", "S1000 ", "P3 ", "#1=2 ", "#<x>=[1+2] ", "[", "]", "(", ")",
    "(MSG,hi)", ";", "/", "%", "\n", "O100 sub\n", "O100 endsub\n", "O100 call [1] [2]\n", "O1 if [#1 GT 0]\n",
    "O1 endif\n", "O2 while [1]\n", "O2 endwhile\n", "O3 repeat [1000000]\n", "O3 endrepeat\n", "ATAN[1]/[0]",
    "SQRT[-1]", "1e308", "-0", "99999999999", ".", "..", "**", "MOD", "EXISTS[#<y>]", "#5399", "N10 ",
};

std::vector<std::string> load(const std::vector<std::string>& paths) {
  std::vector<std::string> out;
  auto add = [&](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    out.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  for (const auto& p : paths) {
    if (fs::is_directory(p)) {
      std::vector<fs::path> files;
      for (const auto& e : fs::recursive_directory_iterator(p))
        if (e.is_regular_file() && e.path().extension() != ".rs274" && e.file_size() < (1u << 20))
          files.push_back(e.path());
      std::sort(files.begin(), files.end());  // directory order is not deterministic
      for (const auto& f : files) add(f);
    } else if (fs::is_regular_file(p)) {
      add(p);
    }
  }
  return out;
}

void mutate(std::string& s, const std::vector<std::string>& corpus, std::mt19937_64& rng, std::size_t max_len) {
  auto pick = [&](std::size_t n) { return n == 0 ? 0 : static_cast<std::size_t>(rng() % n); };
  const int n = 1 + static_cast<int>(rng() % 6);
  for (int k = 0; k < n; ++k) {
    switch (rng() % 7) {
      case 0:
        if (!s.empty()) s[pick(s.size())] ^= static_cast<char>(1u << (rng() % 8));
        break;
      case 1:
        s.insert(s.begin() + static_cast<std::ptrdiff_t>(pick(s.size() + 1)), static_cast<char>(rng() % 256));
        break;
      case 2:
        if (!s.empty()) {
          const std::size_t at = pick(s.size());
          s.erase(at, 1 + pick(std::min<std::size_t>(16, s.size() - at)));
        }
        break;
      case 3:
      case 4: {
        const char* t = kTokens[pick(std::size(kTokens))];
        s.insert(pick(s.size() + 1), t);
        break;
      }
      case 5:
        if (!s.empty()) {
          const std::size_t at = pick(s.size());
          const std::size_t len = 1 + pick(std::min<std::size_t>(64, s.size() - at));
          s.insert(pick(s.size() + 1), s.substr(at, len));
        }
        break;
      default:
        if (!corpus.empty()) {
          const std::string& o = corpus[pick(corpus.size())];
          s = s.substr(0, pick(s.size() + 1)) + o.substr(pick(o.size() + 1));
        }
    }
  }
  if (s.size() > max_len) s.resize(max_len);
}

}  // namespace

int main(int argc, char** argv) {
  long runs = 1000;
  unsigned long long seed = 1;
  std::size_t max_len = 4096;
  std::vector<std::string> paths;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--runs" && i + 1 < argc) {
      runs = std::atol(argv[++i]);
    } else if (a == "--seed" && i + 1 < argc) {
      seed = std::strtoull(argv[++i], nullptr, 10);
    } else if (a == "--max-len" && i + 1 < argc) {
      max_len = static_cast<std::size_t>(std::atol(argv[++i]));
    } else {
      paths.push_back(a);
    }
  }
  const auto corpus = load(paths);
  for (const auto& c : corpus) LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(c.data()), c.size());
  std::mt19937_64 rng(seed);
  std::string s;
  for (long r = 0; r < runs; ++r) {
    s = corpus.empty() ? std::string() : corpus[rng() % corpus.size()];
    mutate(s, corpus, rng, max_len);
    LLVMFuzzerTestOneInput(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
  }
  std::printf("%s: %zu corpus inputs and %ld mutations (seed %llu): no crash\n", fs::path(argv[0]).filename().c_str(),
              corpus.size(), runs, seed);
  return 0;
}
