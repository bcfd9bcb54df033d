#pragma once
/// @file progress.hpp
/// Progress on stderr: a live bar (done / total, rate, ETA) when stderr is a terminal,
/// otherwise a plain line every 5 % of the work (a CI log or `| tee` shows that work goes on).

#include <chrono>
#include <string>

namespace clothbench {

/// One bar for a piece of long work measured in units (steps, runs).
class Progress {
 public:
  /// @param total  units of the whole job
  /// @param unit   name of a unit, for the rate ("steps", "runs")
  /// @param enabled  false: never print (tests, --quiet)
  Progress(double total, std::string unit, bool enabled = true);
  ~Progress();
  /// Adds done units and redraws at most ten times a second; label says what runs now.
  void advance(double done, const std::string& label);
  /// A line of its own (kept above the bar); printed whether or not stderr is a terminal.
  void line(const std::string& text);

 private:
  void draw(bool force);
  void log_line();
  double m_total, m_done = 0;
  double m_next_percent = 5;  // the next share of the work a plain line is printed at
  std::string m_unit, m_label;
  bool m_enabled, m_live;
  std::chrono::steady_clock::time_point m_start, m_last_draw;
};

}  // namespace clothbench
