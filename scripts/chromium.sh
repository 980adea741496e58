# Headless Chromium for scripts/check-report and scripts/screenshot-report (sourced).
# Debian's chromium package; scripts/test installs it (scripts/common.sh). CHROMIUM overrides.

CHROMIUM="${CHROMIUM:-chromium}"

require_chromium() {
  command -v "$CHROMIUM" >/dev/null 2>&1 && return 0
  echo "$(basename "$0"): no '$CHROMIUM' on PATH: run scripts/test, which installs Debian's chromium" >&2
  return 1
}

# headless_chromium ARGS... : one headless run with a fresh profile, at most 120 s. Root needs
# --no-sandbox; there is no GPU; the profile is new each time so that runs in parallel (ctest)
# do not share a lock.
headless_chromium() {
  local profile status=0
  profile="$(mktemp -d)"
  timeout 120 "$CHROMIUM" --headless --no-sandbox --disable-gpu --disable-dev-shm-usage --no-first-run \
    --user-data-dir="$profile" "$@" || status=$?
  rm -rf "$profile"
  return $status
}
