// The interpreter's state between blocks: modal settings, offsets, feed, tool and current position.
#pragma once

#include <cmath>
#include <optional>
#include <vector>

#include "core/axes.hpp"
#include "program/ir/iso_ops.hpp"
#include "program/iso/modes.hpp"

namespace softmc::program::iso {

// Starts as LinuxCNC starts: G80 (no motion mode) G17 G21 G90 G91.1 G94 G40 G49 G54 G61 G99 G97,
// no feed. (G99: LinuxCNC's interpreter starts in R_PLANE retract mode, #<_retract_r_plane> is 1,
// and no sample configuration's start-up code changes it.)
struct ModalState {
  Motion motion = Motion::None;
  Plane plane = Plane::XY;
  Units units = Units::Mm;
  Distance distance = Distance::Absolute;
  Distance arc_distance = Distance::Incremental;  // G91.1: I/J/K relative to the arc's start point
  FeedMode feed_mode = FeedMode::PerMinute;
  Retract retract = Retract::RPlane;
  std::optional<double> feed_mm_s;  // F converted when programmed; keeps its speed across G20/G21
  // A feed a G94 feed move can use: programmed and above 0 (LinuxCNC takes F0, and refuses the move).
  bool feed_usable() const { return feed_mm_s && *feed_mm_s > 0; }
  double feed_word = 0;             // F as written (G93: inverse minutes)
  bool feed_in_block = false;       // G93: this block had its own F
  PathMode path;                    // G61 at start
  bool path_programmed = false;     // a path word has been emitted (the machine's default applies until then)

  core::Vec position;  // machine coordinates, mm (rotary axes in degrees)

  // Offsets (P-1 program → machine): machine = rotate(program + axis) + work + tool.
  int coord_system = 1;  // G54
  core::Vec work;        // active G5x offset
  double rotation_deg = 0;
  core::Vec axis;        // active G92 offset
  core::Vec tool;        // active tool length offset
  int tool_length_code = 490;  // the G code that set it ×10: G43 430, G43.1 431, G49 490

  SpindleDir spindle = SpindleDir::Stopped;  // M3/M4 turn it, M5 and M19 stop it
  bool css = false;                          // G96 (constant surface speed) / G97
  double css_max_rpm = 0;                    // G96 D (0: no limit), kept for later S words
  double spindle_speed = 0;                  // the last S as written (rpm, or the surface speed under G96)
  bool mist = false, flood = false;          // M7, M8 (M17 both) / M9
  bool feed_override = true;                 // M48 on / M49 off (G84 turns it off while tapping)

  int selected_tool = 0;  // T
  int current_tool = 0;   // after M6 / M61

  Comp comp = Comp::Off;
  double comp_radius_mm = 0;     // of the compensation in effect
  bool comp_moved = false;       // a move was made since G41/G42
  // After G40 ends a compensation that moved, the next move must be straight (LinuxCNC
  // arc_not_allowed): it starts where the tool is, not at the programmed point an arc's centre
  // words count from. A G0/G1 clears it.
  bool arc_not_allowed = false;

  // Canned cycle words that stay in effect while the cycle repeats (LinuxCNC cycle_cc, _r, _p, _q).
  double cycle_cc = 0, cycle_r = 0, cycle_p = 0, cycle_q = 0;
  // G87 words by letter (I J K, mm), kept like LinuxCNC's cycle_i/_j/_k while G87 repeats.
  double cycle_i = 0, cycle_j = 0, cycle_k = 0;
  // The initial level: the third-axis height when the first cycle of a run of cycles began (NAN
  // outside canned cycles). G98 retracts to it for as long as cycles follow one another.
  double cycle_il = NAN;

  // G5 continuation: the previous G5's P Q (program units), for a G5 without I J.
  bool g5_continues = false;
  double g5_p = 0, g5_q = 0;

  // G5.2 … G5.3 block being collected.
  std::vector<core::Vec> nurbs_ctrl;
  std::vector<double> nurbs_weights;
  int nurbs_order = 3;

  bool ended = false;  // M2/M30 executed: later text is not part of the program

  // Set by the parser after a block failed that may have set the feed or the motion mode: the
  // errors that would only echo that failure ("feed rate missing", "no motion mode") are then not
  // reported again. The program is already refused, so what these blocks emit does not matter.
  bool feed_uncertain = false;
  bool motion_uncertain = false;
  bool nurbs_uncertain = false;  // a G5.3 failed: its block's end inside the program is not reported again
};

}  // namespace softmc::program::iso
