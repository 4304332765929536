// `softmc moves` writer: IR instructions → JSON Lines, fast enough to stream million-line programs.
//
// Numbers go straight into one large byte buffer with std::to_chars (no format strings, no
// per-field allocation); the buffer goes out with one fwrite per ~1 MiB. Only the rare free texts
// (messages, file names) go through nlohmann-json for their escaping.
#include "moves.hpp"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string_view>
#include <type_traits>

#include <fcntl.h>
#include <sys/types.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

namespace softmc::app {
namespace {

using program::Instruction;
using program::Program;

// An output buffer that never reallocates in the middle of an object: write_one asks for room for
// a whole instruction first (`need`), then writes without checks. With a FILE it flushes instead
// of growing; in hold mode it keeps full megabytes aside (`held_`, written by write_held) so that
// nothing is copied while a long program streams in; otherwise it grows (moves_jsonl).
class Out {
 public:
  static constexpr std::size_t kFlush = 1 << 20;

  explicit Out(std::FILE* f, bool hold = false) : f_(f), hold_(hold) { buf_.reserve(kFlush + kSlack); }

  // Room for at least `n` more bytes.
  void need(std::size_t n) {
    if (n_ + n <= buf_.size()) return;
    if (hold_ && n_ > 0) {
      held_.push_back(Bytes{std::move(buf_.mem), n_});
      buf_ = Bytes{};
      n_ = 0;
    }
    if (f_ && !hold_ && n_ > 0) flush();
    if (n_ + n > buf_.size()) buf_.reserve(std::max(std::max(buf_.size() * 2, kFlush + kSlack), n_ + n), n_);
  }
  // Hold mode: everything gathered so far, in order, to `f`.
  void write_held(std::FILE* f) {
    for (const auto& h : held_) std::fwrite(h.data(), 1, h.size(), f);
    held_.clear();
    if (n_ > 0) std::fwrite(buf_.data(), 1, n_, f);
    n_ = 0;
  }
  // Flushes once a megabyte has gathered (file output only).
  void maybe_flush() {
    if (f_ && n_ >= kFlush) flush();
  }
  void flush() {
    if (f_ && n_ > 0) std::fwrite(buf_.data(), 1, n_, f_);
    n_ = 0;
  }
  std::string take() { return std::string(buf_.data(), n_); }

  void put(char c) { buf_[n_++] = c; }
  void put(std::string_view s) {
    std::memcpy(buf_.data() + n_, s.data(), s.size());
    n_ += s.size();
  }
  template <std::size_t N>
  void lit(const char (&s)[N]) {  // a string literal, without its terminating zero
    std::memcpy(buf_.data() + n_, s, N - 1);
    n_ += N - 1;
  }

  void integer(long long v) {
    const auto r = std::to_chars(buf_.data() + n_, buf_.data() + buf_.size(), v);
    n_ = static_cast<std::size_t>(r.ptr - buf_.data());
  }

  // Shortest decimal that reads back as the same double, laid out as fmt's "{}" does (the format
  // this output always had): plain digits for decimal exponents -5 < e < 16, else d.ddde±XX.
  // -0 prints as 0 so that dumps do not differ by the sign of zero.
  void number(double v) {
    if (v == 0) return put('0');
    if (short_fixed(v)) return;
    char sci[40];
    const auto r = std::to_chars(sci, sci + sizeof sci, v, std::chars_format::scientific);
    const std::string_view s(sci, static_cast<std::size_t>(r.ptr - sci));
    const std::size_t e_at = s.find('e');
    if (e_at == std::string_view::npos) return put(s);  // inf, nan: never in a valid program
    int exp10 = 0;
    std::from_chars(s.data() + e_at + (s[e_at + 1] == '+' ? 2 : 1), s.data() + s.size(), exp10);
    if (exp10 < -4 || exp10 >= 16) return put(s);
    std::size_t i = 0;
    if (s[0] == '-') {
      put('-');
      i = 1;
    }
    char digits[20];  // the significant digits without the point
    std::size_t nd = 0;
    for (; i < e_at; ++i)
      if (s[i] != '.') digits[nd++] = s[i];
    if (exp10 < 0) {
      lit("0.");
      for (int z = -1; z > exp10; --z) put('0');
      put(std::string_view(digits, nd));
      return;
    }
    const auto int_digits = static_cast<std::size_t>(exp10) + 1;
    if (nd <= int_digits) {
      put(std::string_view(digits, nd));
      for (std::size_t z = nd; z < int_digits; ++z) put('0');
      return;
    }
    put(std::string_view(digits, int_digits));
    put('.');
    put(std::string_view(digits + int_digits, nd - int_digits));
  }

  // The common case, fast: a value of moderate size with at most 9 decimals (a coordinate read
  // from "12.3456" and offset or scaled). Below 1e6 doubles are closer together than 1e-9, so at
  // most one 9-decimal number m / 10^9 reads back as v, and v * 10^9 rounds to it; its trailing
  // zeros off, m gives the shortest digits. False (nothing written) for anything else.
  bool short_fixed(double v) {
    const double a = v < 0 ? -v : v;
    if (!(a >= 1e-4 && a < 1e6)) return false;  // fmt's layout switches to d.ddde-XX below 1e-4
    const auto i = static_cast<std::int64_t>(a * 1e9 + 0.5);  // < 2^50: exact as a double too
    if (static_cast<double>(i) / 1e9 != a) return false;
    auto u = static_cast<std::uint64_t>(i);
    int d = 9;  // strip trailing zeros: 8, then 4, 2, 1 at a time
    if (u % 100000000 == 0) {
      u /= 100000000;
      d -= 8;
    }
    if (d >= 4 && u % 10000 == 0) {
      u /= 10000;
      d -= 4;
    }
    if (d >= 2 && u % 100 == 0) {
      u /= 100;
      d -= 2;
    }
    if (d >= 1 && u % 10 == 0) {
      u /= 10;
      d -= 1;
    }
    static constexpr std::uint64_t kPow10[] = {1, 10, 100, 1000, 10000, 100000, 1000000, 10000000, 100000000,
                                               1000000000};
    if (v < 0) put('-');
    integer(static_cast<long long>(u / kPow10[d]));
    if (d > 0) {
      put('.');
      std::uint64_t f = u % kPow10[d];
      for (int k = d - 1; k >= 0; --k) {
        buf_[n_ + static_cast<std::size_t>(k)] = static_cast<char>('0' + f % 10);
        f /= 10;
      }
      n_ += static_cast<std::size_t>(d);
    }
    return true;
  }

  // number(v), remembered: consecutive moves repeat most of their values (the Z of a contour, the
  // feed), and copying the text is cheaper than making it again.
  struct Memo {
    std::uint64_t bits = 0;
    std::uint8_t len = 1;
    char text[32] = {'0'};  // a double's text is at most 24 characters
  };
  void number(double v, Memo& m) {
    const auto bits = std::bit_cast<std::uint64_t>(v);
    if (bits != m.bits) {
      const std::size_t at = n_;
      number(v);
      const std::size_t len = n_ - at;
      if (len > sizeof m.text) return;  // never for a double; then simply not remembered
      m.bits = bits;
      m.len = static_cast<std::uint8_t>(len);
      std::memcpy(m.text, buf_.data() + at, len);
      return;
    }
    std::memcpy(buf_.data() + n_, m.text, sizeof m.text);  // a fixed size copies faster; `need` left room
    n_ += m.len;
  }

  // `,"key":` then the value.
  template <std::size_t N>
  void key(const char (&k)[N]) {
    lit(",\"");
    lit(k);
    lit("\":");
  }

 private:
  static constexpr std::size_t kSlack = 64 * 1024;  // room for one ordinary instruction past kFlush
  // Uninitialised bytes (a std::vector<char> would first zero every megabyte it is given).
  struct Bytes {
    std::unique_ptr<char[]> mem;
    std::size_t cap = 0;
    char* data() { return mem.get(); }
    const char* data() const { return mem.get(); }
    std::size_t size() const { return cap; }
    char& operator[](std::size_t i) { return mem[i]; }
    void reserve(std::size_t n, std::size_t keep = 0) {  // grows to n bytes, keeping the first `keep`
      std::unique_ptr<char[]> m(new char[n]);
      if (keep > 0) std::memcpy(m.get(), mem.get(), keep);
      mem = std::move(m);
      cap = n;
    }
  };

  std::FILE* f_;
  bool hold_;
  Bytes buf_;
  std::vector<Bytes> held_;
  std::size_t n_ = 0;
};

// An upper bound of the bytes write_one makes for `ins` (before JSON escaping of texts, which
// `text` accounts for itself).
std::size_t bound(const Program& prog, const Instruction& ins) {
  std::size_t n = 2048;  // every fixed-size object, with all nine axes, fits
  if (ins.loc.file != 0 && ins.loc.file < prog.files.size()) n += 6 * prog.files[ins.loc.file].size() + 16;
  if (const auto* nu = std::get_if<program::Nurbs>(&ins.op)) n += 300 * (nu->ctrl.size() + nu->weights.size());
  if (const auto* m = std::get_if<program::Message>(&ins.op)) n += 6 * m->text.size() + 16;
  return n;
}

// A JSON string (escaped; bytes that are not UTF-8 become U+FFFD rather than an exception).
void text(Out& o, std::string_view s) {
  o.put(nlohmann::json(std::string(s)).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
}

// The last end point and feed written, for Out::number's memo.
struct Memos {
  Out::Memo end[core::kMaxAxes];
  Out::Memo feed;
};

void axes_obj(Out& o, const core::Vec& v, core::AxisMask axes, Out::Memo* memo = nullptr) {
  o.put('{');
  bool first = true;
  for (std::size_t i = 0; i < core::kMaxAxes; ++i) {
    if (!(axes & core::axis_bit(i))) continue;
    if (!first) o.put(',');
    first = false;
    o.put('"');
    o.put(core::letter(i));
    o.lit("\":");
    if (memo) o.number(v[i], memo[i]);
    else o.number(v[i]);
  }
  o.put('}');
}

void boolean(Out& o, bool v) {
  if (v) o.lit("true");
  else o.lit("false");
}

void plane(Out& o, std::uint8_t a0, std::uint8_t a1) {
  o.key("plane");
  o.put('"');
  o.put(core::letter(a0));
  o.put(core::letter(a1));
  o.put('"');
}

template <std::size_t N>
void type(Out& o, const char (&t)[N]) {
  o.lit(",\"type\":\"");
  o.lit(t);
  o.put('"');
}

void write_one(Out& o, const Program& prog, const Instruction& ins, core::AxisMask axes, Memos& memo) {
  o.need(bound(prog, ins));
  o.lit("{\"line\":");
  o.integer(ins.loc.line);
  o.lit(",\"col\":");
  o.integer(ins.loc.col);
  if (ins.loc.file != 0 && ins.loc.file < prog.files.size()) {
    o.key("file");
    text(o, prog.files[ins.loc.file]);
  }
  std::visit(
      [&](const auto& alt) {
        const auto& op = program::unboxed(alt);  // a Boxed payload as itself
        using T = std::decay_t<decltype(op)>;
        using namespace program;
        if constexpr (std::is_same_v<T, Rapid>) {
          type(o, "rapid");
          o.key("end");
          axes_obj(o, op.end, axes, memo.end);
        } else if constexpr (std::is_same_v<T, Linear>) {
          type(o, "feed");
          o.key("end");
          axes_obj(o, op.end, axes, memo.end);
          o.key("feed_mm_s");
          o.number(op.feed_mm_s, memo.feed);
        } else if constexpr (std::is_same_v<T, Arc>) {
          type(o, "arc");
          o.key("end");
          axes_obj(o, op.end, axes, memo.end);
          o.lit(",\"center\":{\"");
          o.put(core::letter(op.axis0));
          o.lit("\":");
          o.number(op.center0);
          o.lit(",\"");
          o.put(core::letter(op.axis1));
          o.lit("\":");
          o.number(op.center1);
          o.put('}');
          plane(o, op.axis0, op.axis1);
          o.key("normal");
          o.put('"');
          o.put(core::letter(op.normal));
          o.put('"');
          o.key("turns");
          o.integer(op.turns < 0 ? -static_cast<long long>(op.turns) : op.turns);
          o.key("direction");
          if (op.turns < 0) o.lit("\"cw\"");
          else o.lit("\"ccw\"");
          o.key("feed_mm_s");
          o.number(op.feed_mm_s, memo.feed);
        } else if constexpr (std::is_same_v<T, Bezier>) {
          type(o, "spline");
          o.key("end");
          axes_obj(o, op.end, axes, memo.end);
          o.key("degree");
          o.integer(op.degree);
          o.key("control1");
          axes_obj(o, op.ctrl1, axes);
          if (op.degree == 3) {
            o.key("control2");
            axes_obj(o, op.ctrl2, axes);
          }
          plane(o, op.axis0, op.axis1);
          o.key("feed_mm_s");
          o.number(op.feed_mm_s, memo.feed);
        } else if constexpr (std::is_same_v<T, Nurbs>) {
          type(o, "nurbs");
          o.key("end");
          axes_obj(o, op.ctrl.empty() ? core::Vec{} : op.ctrl.back(), axes);
          o.key("order");
          o.integer(op.order);
          o.lit(",\"controls\":[");
          for (std::size_t i = 0; i < op.ctrl.size(); ++i) {
            if (i) o.put(',');
            axes_obj(o, op.ctrl[i], axes);
          }
          o.lit("],\"weights\":[");
          for (std::size_t i = 0; i < op.weights.size(); ++i) {
            if (i) o.put(',');
            o.number(op.weights[i]);
          }
          o.put(']');
          o.key("feed_mm_s");
          o.number(op.feed_mm_s, memo.feed);
        } else if constexpr (std::is_same_v<T, Dwell>) {
          type(o, "dwell");
          o.key("seconds");
          o.number(op.seconds);
        } else if constexpr (std::is_same_v<T, ToolSwitch>) {
          type(o, "spindle");
          o.key("on");
          boolean(o, op.on);
        } else if constexpr (std::is_same_v<T, SpindleSpeed>) {
          type(o, "spindle_speed");
          o.key("rpm");
          o.number(op.rpm);
          o.key("css");
          boolean(o, op.css);
          o.key("surface_m_min");
          o.number(op.surface_m_min);
          o.key("max_rpm");
          o.number(op.max_rpm);
        } else if constexpr (std::is_same_v<T, MFunction>) {
          type(o, "m");
          o.key("number");
          o.integer(op.number);
          o.key("group");
          o.integer(op.group);
        } else if constexpr (std::is_same_v<T, ToolSelect>) {
          type(o, "tool_select");
          o.key("tool");
          o.integer(op.tool);
        } else if constexpr (std::is_same_v<T, ToolChange>) {
          type(o, "tool_change");
          o.key("tool");
          o.integer(op.tool);
        } else if constexpr (std::is_same_v<T, Pause>) {
          type(o, "pause");
          o.key("optional");
          boolean(o, op.optional);
        } else if constexpr (std::is_same_v<T, PathMode>) {
          type(o, "path_mode");
          o.key("mode");
          if (op.kind == PathKind::ExactPath) o.lit("\"exact_path\"");
          else if (op.kind == PathKind::ExactStop) o.lit("\"exact_stop\"");
          else o.lit("\"blend\"");
          o.key("tolerance_mm");
          o.number(op.tolerance_mm);
          o.key("naive_tolerance_mm");
          o.number(op.naive_tolerance_mm);
          o.key("continuous");
          boolean(o, op.continuous);
        } else if constexpr (std::is_same_v<T, OffsetsChanged>) {
          type(o, "offsets");
          o.key("coord_system");
          o.integer(op.coord_system);
          o.key("work");
          axes_obj(o, op.work, axes);
          o.key("axis");
          axes_obj(o, op.axis, axes);
          o.key("tool");
          axes_obj(o, op.tool, axes);
          o.key("rotation_deg");
          o.number(op.rotation_deg);
        } else if constexpr (std::is_same_v<T, DigitalOutput>) {
          type(o, "digital_output");
          o.key("index");
          o.integer(op.index);
          o.key("on");
          boolean(o, op.on);
          o.key("synced");
          boolean(o, op.synced);
        } else if constexpr (std::is_same_v<T, AnalogOutput>) {
          type(o, "analog_output");
          o.key("index");
          o.integer(op.index);
          o.key("value");
          o.number(op.value);
          o.key("synced");
          boolean(o, op.synced);
        } else if constexpr (std::is_same_v<T, WaitInput>) {
          type(o, "wait_input");
          o.key("index");
          o.integer(op.index);
          o.key("digital");
          boolean(o, op.digital);
          o.key("mode");
          o.integer(op.mode);
          o.key("timeout_s");
          o.number(op.timeout_s);
        } else if constexpr (std::is_same_v<T, Message>) {
          type(o, "message");
          o.key("kind");
          if (op.kind == MessageKind::Msg) o.lit("\"msg\"");
          else if (op.kind == MessageKind::Debug) o.lit("\"debug\"");
          else o.lit("\"print\"");
          o.key("text");
          text(o, op.text);
        } else if constexpr (std::is_same_v<T, ProgramEnd>) {
          type(o, "end");
          o.key("rewind");
          boolean(o, op.rewind);
        } else if constexpr (requires { spc_text(op); }) {  // SPC payloads: their canonical text
          const std::string t = spc_text(op);
          o.need(6 * t.size() + 64);
          type(o, "spc");
          o.key("text");
          text(o, t);
        } else {
          type(o, "other");
          o.key("op");
          o.integer(static_cast<long long>(ins.op.index()));
        }
      },
      ins.op);
  o.lit("}\n");
}

}  // namespace

void write_moves(std::FILE* out, const Program& prog, core::AxisMask axes) {
  Out o(out);
  Memos memo;
  for (const auto& ins : prog.instructions) {
    write_one(o, prog, ins, axes, memo);
    o.maybe_flush();
  }
  o.flush();
}

core::Diagnostics write_program_moves(std::FILE* out, const std::string& path, program::iso::ParseOptions opt,
                                      core::AxisMask axes) {
  // Output that can be cut back (a file, /dev/null) is written as it comes and truncated to where
  // it began if the program has an error; anything else (a pipe, a terminal) is held until the
  // program is known to be good.
  const int fd = ::fileno(out);
  off_t start = std::fflush(out) == 0 && fd >= 0 ? ::lseek(fd, 0, SEEK_CUR) : off_t{-1};
  if (start >= 0 && (::fcntl(fd, F_GETFL) & O_APPEND)) start = ::lseek(fd, 0, SEEK_END);  // ">>": writes go to the end
  const bool seekable = start >= 0;
  Out o(seekable ? out : nullptr, !seekable);
  Memos memo;
  opt.sink = [&](const Program& batch) {
    for (const auto& ins : batch.instructions) {
      write_one(o, batch, ins, axes, memo);
      o.maybe_flush();
    }
  };
  auto r = program::iso::parse_file(path, opt);
  const bool good = !core::has_errors(r.diagnostics);
  if (!seekable) {
    if (good) o.write_held(out);
  } else if (good) {
    o.flush();
  } else {
    std::fflush(out);
    if (::ftruncate(fd, start) == 0) std::fseek(out, start, SEEK_SET);  // a device such as /dev/null keeps nothing
  }
  return std::move(r.diagnostics);
}

std::string moves_jsonl(const Program& prog, core::AxisMask axes) {
  Out o(nullptr);
  Memos memo;
  for (const auto& ins : prog.instructions) write_one(o, prog, ins, axes, memo);
  return o.take();
}

}  // namespace softmc::app
