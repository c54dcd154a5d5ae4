//! The `coverplan bench` command line: which benchmark to run, and its options.

use std::path::PathBuf;

use super::{Options, corridor, energy, farm, fleet, ground, inspection, oblique, patrol, queue, resume, routing, run, terrain, wind, workers};

/// Time the planners on the generated fields and print a table.
#[derive(clap::Args)]
pub struct BenchArgs {
    /// Folder with index.json and the field files.
    #[arg(long, default_value = "tests/fixtures/random-fields")]
    pub data: PathBuf,
    /// Only this planner.
    #[arg(long)]
    pub planner: Option<String>,
    /// Runs per field.
    #[arg(long, default_value_t = 3)]
    pub repeats: usize,
    /// multirotor (default) or fixed_wing (turning at half the line spacing).
    #[arg(long)]
    pub vehicle: Option<String>,
    /// Line spacing in metres for every field (default: a twentieth of the square root of its area).
    #[arg(long)]
    pub spacing: Option<f64>,
    /// Only these fields (file names without .json), comma-separated.
    #[arg(long, value_delimiter = ',')]
    pub fields: Vec<String>,
    /// Where lines end at slanted edges: full_width, balanced or centre_line (default: the planners' own).
    #[arg(long, value_parser = ["full_width", "balanced", "centre_line"])]
    pub ends: Option<String>,
    /// Fields2Cover's fixed-wing configuration (width max(8, √area/25), radius half of it, zones 1 m off) on the fields h*_00, beside its figures.
    #[arg(long)]
    pub fields2cover: bool,
    /// With --fields2cover: the fields of every seed (h*_00 to h*_03), with a table of ours by seed and bin of holes.
    #[arg(long)]
    pub every_seed: bool,
    /// The holes are only not to be covered and may be flown over (Fields2Cover's semantics), not no-fly zones.
    #[arg(long)]
    pub overfly_holes: bool,
    /// Instead: route 100, 300 and 600 parallel lines with Dubins turns.
    #[arg(long)]
    pub routing: bool,
    /// Instead: E-Spiral against E-BF energy on generated polygons, and EG-CPP time by grid size.
    #[arg(long)]
    pub energy: bool,
    /// The generator's seed for `--energy`'s polygons (another seed, other polygons of the same classes).
    #[arg(long, default_value_t = 0x5eed_0002)]
    pub seed: u64,
    /// Instead: the patrolling experiments of seed 002 §5.3 (30 seeds a row) beside the published means.
    #[arg(long)]
    pub patrol: bool,
    /// Instead: the last landing of 1, 2, 4 and 8 drones sharing each field, against the ideal.
    #[arg(long)]
    pub fleet: bool,
    /// Instead: ground vehicles (planner headland) on the real fields beside Fields2Cover's figures, and on the generated fields.
    #[arg(long)]
    pub ground: bool,
    /// Instead: inspection (seed 001's first scene rebuilt, and a barn): budget × share seen × time.
    #[arg(long)]
    pub inspection: bool,
    /// Instead: plans at 60 m above the ground of the public terrains (`tests/fixtures/terrain`)
    /// and of generated ones, beside the flat plan: vertices per km, the time the profile adds,
    /// energy.
    #[arg(long)]
    pub terrain: bool,
    /// Instead: resuming each plan of the generated fields (multirotor and fixed wing) at ten
    /// cuts along its path: time, and length against what the original had left.
    #[arg(long)]
    pub resume: bool,
    /// Instead: plans made for the wind (0.3 and 0.5 of the airspeed, 8 directions) against
    /// the still-air plan flown in the same wind, multirotor and fixed wing.
    #[arg(long)]
    pub wind: bool,
    /// Instead: planner `corridor` on generated winding corridors 220 km long and 60 m wide,
    /// multirotor and fixed wing, one row per seed (`--repeats` seeds).
    #[arg(long)]
    pub corridor: bool,
    /// Instead: pattern `oblique` against the nadir grid on a square field and the generated
    /// fields: length, photos, each pass's share imaged (beside MAVLink PR #1508's figures).
    #[arg(long)]
    pub oblique: bool,
    /// Instead: farm schedules of generated farms (100 to 1 000 fields, 2 to 8 machines), then a
    /// farm plan of `--farm-fields` generated fields through the service in process.
    #[arg(long)]
    pub farm: bool,
    /// With `--farm`: the fields of the farm plan through the service (0: none).
    #[arg(long, default_value_t = 1000)]
    pub farm_fields: usize,
    /// Instead: one server's worker pool on SQLite with each of these worker counts (`1,2,4`):
    /// a batch of plans of the generated fields (`--repeats` multirotor plans of each, a
    /// fixed-wing plan of each with 4 holes or more): plans per minute, speed-up, cores busy.
    #[arg(long, value_delimiter = ',')]
    pub workers: Vec<usize>,
    /// Instead: the shared job queue on the PostgreSQL server at this admin URL
    /// (postgres://user@host:port/postgres): plans per minute with 1, 2 and 4 replicas, and
    /// the time of one claim at 10 000 queued plans.
    #[arg(long, value_name = "ADMIN_URL")]
    pub queue: Option<String>,
    /// Print the table as a section of `docs/benchmarks.md`: the command that regenerates it,
    /// then the table.
    #[arg(long)]
    pub markdown: bool,
}

/// Runs the benchmark `args` asks for and prints its table; with `--markdown`, as a section of
/// `docs/benchmarks.md` headed by the command that regenerates it.
pub fn run_command(args: BenchArgs) -> anyhow::Result<()> {
    let markdown = args.markdown;
    let table = table(args)?;
    if markdown {
        // a server's address is this machine's own: the section names what to pass instead
        let mut command: Vec<String> = std::env::args().skip(1).filter(|a| a != "--markdown").collect();
        for k in 1..command.len() {
            if command[k - 1] == "--queue" {
                command[k] = "ADMIN_URL".into();
            }
        }
        print!("```sh\ncargo run --release --features bench -- {} --markdown\n```\n\n{table}", command.join(" "));
    } else {
        print!("{table}");
    }
    Ok(())
}

fn table(args: BenchArgs) -> anyhow::Result<String> {
    Ok(match args {
        BenchArgs { energy: true, repeats, seed, .. } => energy::run(repeats.max(1) * 4, seed),
        BenchArgs { ref workers, data, repeats, .. } if !workers.is_empty() => tokio::runtime::Runtime::new()?.block_on(self::workers::run(&data, repeats.max(1), workers))?,
        BenchArgs { queue: Some(admin), .. } => tokio::runtime::Runtime::new()?.block_on(queue::run(&admin))?,
        BenchArgs { farm: true, repeats, farm_fields, .. } => farm::run(repeats.max(1), farm_fields)?,
        BenchArgs { patrol: true, .. } => patrol::run(),
        BenchArgs { inspection: true, repeats, .. } => inspection::run(repeats),
        BenchArgs { ground: true, data, repeats, fields, .. } => ground::run(&data, repeats, &fields)?,
        BenchArgs { fleet: true, data, fields, .. } => fleet::run(&data, &fields)?,
        BenchArgs { routing: true, .. } => routing(),
        BenchArgs { resume: true, data, fields, .. } => resume::run(&data, &fields)?,
        BenchArgs { wind: true, data, fields, .. } => wind::run(&data, &fields)?,
        BenchArgs { corridor: true, repeats, .. } => corridor::run(repeats.max(1))?,
        BenchArgs { oblique: true, data, fields, .. } => oblique::run(&data, &fields)?,
        BenchArgs { terrain: true, repeats, .. } => terrain::run(std::path::Path::new("tests/fixtures/terrain"), repeats)?,
        BenchArgs { data, planner, repeats, vehicle, spacing, fields, ends, fields2cover, every_seed, overfly_holes, .. } => {
            let options = Options {
                planner: planner.as_deref(),
                repeats,
                vehicle: vehicle.as_deref(),
                spacing_m: spacing,
                fields: &fields,
                ends: ends.as_deref(),
                fields2cover,
                every_seed,
                overfly_holes,
            };
            run(&data, &options)?
        }
    })
}
