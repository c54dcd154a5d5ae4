"""schemathesis against the real server and its own OpenAPI document.

Starts `coverplan serve` (the binary the test command built) on a fresh database with API keys,
runs schemathesis with every check and a tenant's key, then reads the server's own /metrics to
count what was asked and answered: it fails unless schemathesis passed, at least MIN_REQUESTS
requests were made and none was answered 5xx.

Usage: python fuzz_api.py BINARY [--max-examples N] [--seed N] [schemathesis options]
"""

import argparse
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

MIN_REQUESTS = 5000


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def make_key(binary, db, tenant, admin=False):
    args = [binary, "keys", "create", "--tenant", tenant, "--database-url", db] + (["--admin"] if admin else [])
    out = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    return out.strip().splitlines()[-1]


def get(url, key):
    request = urllib.request.Request(url, headers={"Authorization": f"Bearer {key}"})
    with urllib.request.urlopen(request, timeout=10) as r:
        return r.read().decode()


def requests_by_status(metrics):
    """(method, route, status) -> count, from the OpenMetrics text."""
    counts = {}
    for m in re.finditer(r'^coverplan_http_requests_total\{method="([^"]+)",route="([^"]+)",status="(\d+)"\} (\S+)$', metrics, re.M):
        counts[(m[1], m[2], int(m[3]))] = float(m[4])
    return counts


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("binary")
    parser.add_argument("--max-examples", type=int, default=60)
    parser.add_argument("--seed", type=int, default=20261124)
    # anything else goes to schemathesis (for example --include-operation-id create_plan)
    args, passed_on = parser.parse_known_args()
    work = tempfile.mkdtemp(prefix="coverplan-fuzz-")
    db = os.path.join(work, "fuzz.db")
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    fuzzer_key = make_key(args.binary, db, "fuzzer")
    operator_key = make_key(args.binary, db, "operator", admin=True)
    env = dict(
        os.environ,
        COVERPLAN_ADDR=f"127.0.0.1:{port}",
        COVERPLAN_DATABASE_URL=db,
        COVERPLAN_WORKERS="2",
        COVERPLAN_REQUIRE_AUTH="true",
        # the fuzzer is one client sending as fast as it can: no rate or queue limit in its way,
        # and plans of random parameters stopped soon
        COVERPLAN_RATE_PER_S="100000",
        COVERPLAN_MAX_QUEUED="100000",
        COVERPLAN_JOB_TIMEOUT_S="5",
        COVERPLAN_LOG="warn",
        COVERPLAN_TILE_URL="",
    )
    fuzz_env = dict(os.environ, SCHEMATHESIS_HOOKS="hooks", PYTHONPATH=os.path.dirname(os.path.abspath(__file__)))
    server = subprocess.Popen([args.binary, "serve"], env=env, cwd=work)
    try:
        for _ in range(200):
            try:
                urllib.request.urlopen(f"{base}/readyz", timeout=1)
                break
            except OSError:
                time.sleep(0.05)
        else:
            sys.exit("the server did not start")
        report = os.path.join(work, "report.json")
        here = os.path.dirname(os.path.abspath(__file__))
        command = [
            sys.executable, os.path.join(here, "run_schemathesis.py"),
            "--config-file", os.path.join(here, "schemathesis.toml"),
            "run",
            f"{base}/openapi.json",
            "--header", f"Authorization: Bearer {fuzzer_key}",
            "--max-examples", str(args.max_examples),
            "--seed", str(args.seed),
            "--workers", "2",
            "--request-timeout", "30",
            "--generation-database", "none",
            "--no-color",
            "--report", "json",
            "--report-json-path", report,
        ] + passed_on
        print("fuzz:", " ".join(c if "Bearer" not in c else "Authorization: Bearer …" for c in command), flush=True)
        fuzzed = subprocess.run(command, env=fuzz_env)
        counts = requests_by_status(get(f"{base}/metrics", operator_key))
        total = sum(counts.values())
        errors = {k: v for k, v in counts.items() if k[2] >= 500}
        by_status = {}
        for (_, _, status), n in counts.items():
            by_status[status] = by_status.get(status, 0) + n
        print(f"fuzz: {total:.0f} requests answered, by status {json.dumps(dict(sorted(by_status.items())))}", flush=True)
        failed = []
        if fuzzed.returncode != 0:
            failed.append(f"schemathesis exited {fuzzed.returncode}")
        if total < MIN_REQUESTS:
            failed.append(f"only {total:.0f} requests (at least {MIN_REQUESTS} wanted)")
        if errors:
            failed.append(f"5xx answers: {errors}")
        if failed:
            sys.exit("fuzz: " + "; ".join(failed))
        print("fuzz: ok")
    finally:
        server.terminate()
        server.wait(timeout=30)
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
