#!/usr/bin/env bash
# Runs every test of coverplan on a fresh machine: installs what the tests need (Debian's
# Chromium and npm's playwright-core for the map page test; Debian's PostgreSQL server, on which
# the store, queue and API tests run a second time; the independent readers of the
# exported files: PyPI's pymavlink, fastkml, jsonschema, pyshp and utm in a virtual environment,
# npm's isoxml; PyPI's schemathesis for the API fuzz; PyPI's kubernetes-validate and yamllint for
# the Kubernetes manifests), then runs them.
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v cargo >/dev/null; then
  echo "cargo is needed: install Rust from https://rustup.rs" >&2
  exit 1
fi
packages=""
[ -x /usr/bin/chromium ] || packages="$packages chromium"
ls /usr/lib/postgresql/*/bin/initdb >/dev/null 2>&1 || packages="$packages postgresql"
python3 -c "import ensurepip, venv" 2>/dev/null || packages="$packages python3 python3-venv"
if [ -n "$packages" ]; then
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq $packages
fi
(cd tests/browser && npm ci --no-audit --no-fund)
(cd tests/interop && npm ci --no-audit --no-fund)
# the interop tests find this interpreter through COVERPLAN_PYTHON
venv="${COVERPLAN_VENV:-${HOME}/.cache/coverplan-venv}"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/pip" install -q --disable-pip-version-check -r tests/interop/requirements.txt
export COVERPLAN_PYTHON="$venv/bin/python"
# schemathesis in a virtual environment of its own (its pins need not agree with the readers')
fuzz_venv="${COVERPLAN_FUZZ_VENV:-${HOME}/.cache/coverplan-fuzz-venv}"
[ -x "$fuzz_venv/bin/python" ] || python3 -m venv "$fuzz_venv"
"$fuzz_venv/bin/pip" install -q --disable-pip-version-check -r tests/fuzz/requirements.txt

# the Kubernetes manifests' offline checks (kubernetes-validate, yamllint) in one of their own
deploy_venv="${COVERPLAN_DEPLOY_VENV:-${HOME}/.cache/coverplan-deploy-venv}"
[ -x "$deploy_venv/bin/python" ] || python3 -m venv "$deploy_venv"
"$deploy_venv/bin/pip" install -q --disable-pip-version-check -r tests/deploy/requirements.txt

for component in rustfmt clippy; do
  rustup component list --installed 2>/dev/null | grep -q "^$component" || rustup component add "$component"
done
# style, lints and manifests first: they fail in seconds
cargo fmt --all --check
"$deploy_venv/bin/python" tests/deploy/check_kubernetes.py
cargo clippy --workspace --all-targets --all-features --locked -- -D warnings
cargo test --workspace --all-targets --all-features --locked --no-fail-fast
# every test that starts the application (tests/it/db/) again on a throwaway PostgreSQL server
# (with the test of two replicas sharing it, one killed mid-plan)
eval "$(bash tests/postgres.sh start)"
trap 'bash tests/postgres.sh stop "$COVERPLAN_TEST_PGDATA"' EXIT
cargo test -p coverplan --test it --all-features --locked --no-fail-fast -- db::
unset COVERPLAN_TEST_POSTGRES
# --all-targets leaves out the documentation examples
cargo test --workspace --doc --locked
# the map page in Chromium, against the server binary the line above built
node tests/browser/map.test.mjs
# schemathesis against the same binary and its own OpenAPI document: every check, a tenant's key
"$fuzz_venv/bin/python" tests/fuzz/fuzz_api.py "${CARGO_TARGET_DIR:-target}/debug/coverplan" --max-examples 100
