#pragma once
/// @file exit_codes.hpp
/// The exit status of every clothbench command (README, "Commands": the same table).

namespace clothbench::cli {

constexpr int kExitOk = 0;
constexpr int kExitGateFailed = 1;      // check: a gate failed
constexpr int kExitUserError = 2;       // a UserError or a command-line parse error
constexpr int kExitInternalError = 70;  // a bug in clothbench (EX_SOFTWARE of sysexits.h)
constexpr int kExitInterrupted = 130;   // Ctrl-C or SIGTERM (128 + SIGINT, as shells report)

}  // namespace clothbench::cli
