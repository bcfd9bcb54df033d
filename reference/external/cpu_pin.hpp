#pragma once
/// @file cpu_pin.hpp
/// One CPU for the harness thread and the external engine it speaks to (share_cpu = true):
/// the calling thread is pinned to one CPU of its allowed set for the pin's life, so that a
/// program it starts meanwhile inherits that CPU, and its previous set comes back at the end.

#include <sched.h>

namespace clothbench::reference {

/// Pins the calling thread to one CPU of its allowed set for the object's life. The CPU is the
/// allowed one that the fewest live pins of this process hold, the one the thread runs on now
/// first among equals, then the next numbers round: the threads of a -j N sweep get distinct
/// CPUs while there are enough, and share them evenly when there are more threads. Where the
/// system refuses (sched_setaffinity fails, as in some restricted containers) the thread stays
/// unpinned, and the first refusal in the process says so once on stderr (not an error).
class CpuPin {
 public:
  CpuPin();
  /// Gives the pinned thread its previous allowed set back (whichever thread destroys the pin)
  /// and frees the CPU for later pins.
  ~CpuPin();
  CpuPin(const CpuPin&) = delete;
  CpuPin& operator=(const CpuPin&) = delete;

  /// The CPU the thread is pinned to; -1 when it runs unpinned.
  int cpu() const { return m_cpu; }

 private:
  int m_cpu = -1;
  int m_thread = 0;      // kernel id of the pinned thread
  cpu_set_t m_previous;  // its allowed set before the pin
};

}  // namespace clothbench::reference
