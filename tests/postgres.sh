#!/usr/bin/env bash
# A throwaway PostgreSQL server for the tests, from Debian's `postgresql` package:
#   eval "$(bash tests/postgres.sh start)"   prints `export COVERPLAN_TEST_POSTGRES=…` and
#                                            `export COVERPLAN_TEST_PGDATA=…`
#   bash tests/postgres.sh stop "$COVERPLAN_TEST_PGDATA"
# initdb refuses to run as root, so as root the server runs as the `postgres` user the package
# creates. Data lives in a temporary folder; fsync is off (a test server needs no durability).
set -euo pipefail

bin="$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -n 1)"
[ -x "$bin/initdb" ] || { echo "PostgreSQL's server programs are missing: apt-get install postgresql" >&2; exit 1; }

as_owner() {
  if [ "$(id -u)" -eq 0 ]; then runuser -u postgres -- "$@"; else "$@"; fi
}

case "${1:-}" in
  start)
    data="$(mktemp -d /tmp/coverplan-pg.XXXXXX)"
    [ "$(id -u)" -eq 0 ] && chown postgres: "$data"
    port="$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')"
    as_owner "$bin/initdb" -D "$data/db" -U coverplan --auth=trust -E UTF8 >"$data/initdb.log" 2>&1 \
      || { cat "$data/initdb.log" >&2; exit 1; }
    as_owner "$bin/pg_ctl" -D "$data/db" -l "$data/server.log" -w -t 60 \
      -o "-p $port -k $data -c listen_addresses=127.0.0.1 -c max_connections=400 -c fsync=off -c synchronous_commit=off -c full_page_writes=off" \
      start >/dev/null || { cat "$data/server.log" >&2; exit 1; }
    echo "export COVERPLAN_TEST_POSTGRES=postgres://coverplan@127.0.0.1:$port/postgres"
    echo "export COVERPLAN_TEST_PGDATA=$data"
    ;;
  stop)
    data="${2:?the folder printed by start}"
    as_owner "$bin/pg_ctl" -D "$data/db" -m fast -w stop >/dev/null || true
    rm -rf "$data"
    ;;
  *)
    echo "usage: $0 start | stop DATA" >&2
    exit 2
    ;;
esac
