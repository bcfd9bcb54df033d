#!/usr/bin/env bash
# Runs its arguments as a command when headless chromium is there (CHROMIUM, default
# /usr/bin/chromium); otherwise the test is skipped (exit 77) and says why.
chromium=${CHROMIUM:-/usr/bin/chromium}
if [ ! -x "$chromium" ]; then
  echo "SKIPPED: needs a browser: $chromium not installed (apt-get install chromium)"
  exit 77
fi
exec "$@"
