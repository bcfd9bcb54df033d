#include "reference/external/cpu_pin.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <iostream>
#include <mutex>
#include <string>
#include <vector>

namespace clothbench::reference {
namespace {

/// Live pins by CPU number, for the whole process (threads of a sweep pin at once).
struct PinBook {
  std::mutex mutex;
  std::vector<int> pins = std::vector<int>(CPU_SETSIZE, 0);
};

PinBook& pin_book() {
  static PinBook book;
  return book;
}

/// The CPU of allowed with the fewest live pins in book: now (where the thread runs) first
/// among equals, then the numbers after it, round; -1 when allowed is empty.
int least_pinned(const cpu_set_t& allowed, const PinBook& book, int now) {
  int best = -1;
  const int start = now >= 0 && now < CPU_SETSIZE ? now : 0;
  for (int k = 0; k < CPU_SETSIZE; ++k) {
    const int c = (start + k) % CPU_SETSIZE;
    if (!CPU_ISSET(c, &allowed)) continue;
    if (best < 0 || book.pins[size_t(c)] < book.pins[size_t(best)]) best = c;
  }
  return best;
}

/// Says once per process that pinning was refused and why.
void warn_unpinned(const std::string& why) {
  static std::atomic<bool> said{false};
  if (said.exchange(true)) return;
  std::cerr << "clothbench: share_cpu: " << why
            << "; external engines run unpinned, as without it\n";
}

}  // namespace

CpuPin::CpuPin() : m_thread(static_cast<int>(::gettid())) {
  CPU_ZERO(&m_previous);
  if (::sched_getaffinity(0, sizeof m_previous, &m_previous) != 0) {
    warn_unpinned(std::string("cannot read this thread's CPUs: ") + std::strerror(errno));
    return;
  }
  // choice, pin and booking under one lock, so that a thread pinning at once takes another CPU
  PinBook& book = pin_book();
  const std::lock_guard<std::mutex> lock(book.mutex);
  const int cpu = least_pinned(m_previous, book, ::sched_getcpu());
  if (cpu < 0) return;
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(cpu, &one);
  if (::sched_setaffinity(0, sizeof one, &one) != 0) {
    warn_unpinned("cannot pin a thread to CPU " + std::to_string(cpu) + ": " +
                  std::strerror(errno));
    return;
  }
  m_cpu = cpu;
  ++book.pins[size_t(cpu)];
}

CpuPin::~CpuPin() {
  if (m_cpu < 0) return;
  // by the thread's kernel id: right also when another thread destroys the pin; a thread that
  // has ended meanwhile has nothing to restore
  ::sched_setaffinity(m_thread, sizeof m_previous, &m_previous);
  PinBook& book = pin_book();
  const std::lock_guard<std::mutex> lock(book.mutex);
  --book.pins[size_t(m_cpu)];
}

}  // namespace clothbench::reference
