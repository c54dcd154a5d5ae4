#!/usr/bin/env bash
# Runs every test of coverplan on a fresh machine: installs what the tests need (Debian's
# Chromium and npm's playwright-core for the map page test), then runs them.
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v cargo >/dev/null; then
  echo "cargo is needed: install Rust from https://rustup.rs" >&2
  exit 1
fi
if [ ! -x /usr/bin/chromium ]; then
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq chromium
fi
(cd tests/browser && npm ci --no-audit --no-fund)

cargo test --workspace --all-targets --no-fail-fast
# the map page in Chromium, against the server binary the line above built
node tests/browser/map.test.mjs
