#!/usr/bin/env bash
# Regenerates docs/benchmarks.md: every table is printed by `coverplan bench … --markdown`, which
# heads it with the command that regenerates it. Run from the repository's root:
#   bash docs/benchmarks.sh
# (a release build with the benchmarks: `cargo build --release --features bench`; a few minutes).
set -euo pipefail
cd "$(dirname "$0")/.."
# COVERPLAN_BIN: a release binary built with the benchmarks already (skips the build)
bin="${COVERPLAN_BIN:-}"
if [ -z "$bin" ]; then
  cargo build --release --locked --features bench
  bin=target/release/coverplan
fi
out=docs/benchmarks.md
{
  cat <<'HEAD'
# Benchmarks

Planning time and plan quality, written by `bash docs/benchmarks.sh`: each table below is printed
by the command above it (`coverplan bench … --markdown`), in a release build, on the machine named
at the end. Times are wall-clock planning times without the process start; lengths, coverage and
efficiency do not depend on the machine. The fields are `tests/fixtures/random-fields` (generated,
0 to 15 holes, four per hole count) and `tests/fixtures/real-fields`.

HEAD
  section() {
    local title="$1"; shift
    printf '## %s\n\n' "$title"
    "$bin" bench "$@" --markdown
    printf '\n'
  }
  section "Every planner, multirotor (holes as no-fly zones)" --repeats 1
  section "Fixed wing, 20 m spacing, turning on 10 m" --planner line_gtsp --vehicle fixed_wing --spacing 20 --repeats 1
  section "Beside Fields2Cover, fixed wing, its rules (holes flown over, centre-line ends)" --fields2cover --overfly-holes --ends centre_line --repeats 1
  section "Beside Fields2Cover, fixed wing, holes flown over" --fields2cover --overfly-holes --repeats 1
  section "Beside Fields2Cover, fixed wing, holes as no-fly zones" --fields2cover --repeats 1
  section "The fixed wing's default planner, holes as no-fly zones, every seed" --fields2cover --planner boustrophedon --every-seed --repeats 1
  section "Line-level routing" --routing
  section "E-Spiral against E-BF (seed 002), and EG-CPP" --energy --repeats 3
  section "Ground vehicles" --ground --repeats 3
  section "Farm schedules" --farm --repeats 3
  cat <<'FARM'

The service row: the issue's farm (1 000 fields within 20 km of three depots, four machines) on
this machine; the work takes more than the ten days asked, which the schedule says
(`fits_window`). The gap to the bound is mostly the drive from the depot to each day's fields and
back, which the bound leaves out (docs/methods.md, farms §4).

FARM
  section "One server's worker pool" --workers 1,2 --repeats 8
  cat <<'POOL'
On 2 cores one worker already keeps 1.8 busy (the planners run their parallel phases on rayon's
pool), so a second adds 5 %. The counts that matter (4 to 16 workers on 16 cores) were not
measured: no 16-core machine was lent to this work.

POOL
  # the shared queue runs on a throwaway PostgreSQL server (Debian's `postgresql`)
  eval "$(bash tests/postgres.sh start)"
  trap 'bash tests/postgres.sh stop "$COVERPLAN_TEST_PGDATA"' EXIT
  section "Shared queue on PostgreSQL" --queue "$COVERPLAN_TEST_POSTGRES"
  bash tests/postgres.sh stop "$COVERPLAN_TEST_PGDATA"
  trap - EXIT
  cat <<'QUEUE'
Two replicas use both cores; four share the same two, so they add little here. A claim stays
under a millisecond with a deep queue: the queue's index is in the claim's order (while it was
not, one claim took 16 ms on PostgreSQL and 3.5 ms on SQLite at this depth).

QUEUE
  section "Inspection" --inspection --repeats 3
  section "Patrolling" --patrol
  section "Fleets" --fleet
  section "Over terrain" --terrain --repeats 3
  section "Resuming a plan" --resume
  section "Corridors 220 km long" --corridor --repeats 3
  printf '## Oblique plans\n\n'
  cat <<'OBLIQUE'
Pattern `oblique` against the nadir grid alone. MAVLink PR #1508 flew one pass with the camera
rolled left and right between shots (pseudo-oblique: three views a position, lines further apart);
its field and camera are not published, so its row gives its own figures and ratios, not a plan of
ours. Five full passes (the nadir grid and one per look direction) cost 4.5 to 7.4 times the
nadir grid's length; each oblique pass sees every point of the area from its direction, which one
pass with a rolled camera does only across the track.

OBLIQUE
  "$bin" bench --oblique --markdown
  printf '\n'
  printf '## Wind\n\n'
  cat <<'WIND'
Plans made for a wind against the plan made as in still air, flown in the same wind. Four fields
(0, 4, 8 and 12 holes): a fixed wing plans its turns as trochoids, about 2.9 s a plan (median) on 2
cores, so the 32 fields take about twenty minutes. Coombes et al. (Sensors 18(7):2132, 2018) report "a
significant reduction in flight time" for fixed wings on randomised polygons in winds up to half
the airspeed, chiefly from the sweep direction and from flying outside the polygon; their
abstract gives no single figure, and the paper's tables could not be read here.

WIND
  "$bin" bench --wind --fields h00_00,h04_00,h08_00,h12_00 --markdown
  printf '\n'
  printf 'Measured on: %s, %s cores, %s.\n' "$(uname -m)" "$(nproc)" "$(date -u +%Y-%m-%d)"
} >"$out.new"
mv "$out.new" "$out"
echo "wrote $out"
