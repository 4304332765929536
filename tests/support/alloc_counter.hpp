// Counts heap allocations in a test executable: the proof that the cycle never allocates (DESIGN.md).
#pragma once

namespace softmc::testing {

// Allocations made through the global operator new since the program started.
long allocation_count();

}  // namespace softmc::testing
