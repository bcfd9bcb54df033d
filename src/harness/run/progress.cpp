#include "harness/run/progress.hpp"

#include <unistd.h>
#include <cmath>
#include <cstdio>

namespace clothbench {

Progress::Progress(double total, std::string unit, bool enabled)
    : m_total(total),
      m_unit(std::move(unit)),
      m_enabled(enabled),
      m_live(enabled && ::isatty(STDERR_FILENO)),
      m_start(std::chrono::steady_clock::now()),
      m_last_draw(m_start) {}

Progress::~Progress() {
  if (m_live) std::fputs("\r\033[K", stderr);
}

void Progress::advance(double done, const std::string& label) {
  m_done += done;
  m_label = label;
  draw(false);
}

void Progress::line(const std::string& text) {
  if (!m_enabled) return;
  if (m_live) std::fputs("\r\033[K", stderr);
  std::fprintf(stderr, "%s\n", text.c_str());
  if (m_live) draw(true);
}

void Progress::draw(bool force) {
  if (!m_live) return;
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - m_last_draw < std::chrono::milliseconds(100)) return;
  m_last_draw = now;
  const double elapsed = std::chrono::duration<double>(now - m_start).count();
  const double fraction = m_total > 0 ? std::min(1.0, m_done / m_total) : 1.0;
  const double rate = elapsed > 0 ? m_done / elapsed : 0.0;
  const double eta = rate > 0 ? (m_total - m_done) / rate : 0.0;
  constexpr int width = 30;
  const int filled = static_cast<int>(std::lround(fraction * width));
  std::string bar(static_cast<size_t>(filled), '#');
  bar.resize(width, '.');
  std::fprintf(stderr, "\r\033[K[%s] %3.0f%% %s  %.0f %s/s  ETA %.0f s", bar.c_str(),
               100 * fraction, m_label.c_str(), rate, m_unit.c_str(), eta);
  std::fflush(stderr);
}

}  // namespace clothbench
