#!/usr/bin/env bash
# Runs every test of coverplan on a fresh machine: installs what the tests need, then runs them.
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v cargo >/dev/null; then
  echo "cargo is needed: install Rust from https://rustup.rs" >&2
  exit 1
fi

cargo test --workspace --all-targets --no-fail-fast
