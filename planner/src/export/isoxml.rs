//! ISO 11783-10 TaskData for farm software and tractor terminals (docs/methods.md, interop §6):
//! a zip with `TASKDATA/TASKDATA.XML` holding one partfield per field (its boundary with the
//! holes as interior rings, the no-fly zones as obstacle polygons), a task per partfield, and
//! the sweep lines as guidance: per sweep direction a guidance group with a reference AB line
//! and every swath as its own AB line, the line width being the line spacing; a ground plan's
//! headland passes as curve patterns in a group of their own; the farm's guidance line a ground
//! plan followed as an AB or A+ pattern propagating to both sides, and its tramline swaths as
//! tram lines (`LSG` type 3) of the partfield. Written with quick-xml: no
//! Rust crate writes ISOXML.

use geo::{Centroid, Contains, GeodesicArea, LineString, Point};

use super::xml::Xml;
use super::{COVERAGE_ONLY, ExportJob, ExportRequest, Exporter, Format, number};
use crate::archive;
use crate::error::InputError;
use crate::path::PieceKind;

pub struct TaskData;

/// `PLN` types (ISO 11783-10, the ADAPT ISOv4Plugin enumerations).
pub const PLN_PARTFIELD_BOUNDARY: &str = "1";
pub const PLN_OBSTACLE: &str = "6";
/// `LSG` types.
pub const LSG_EXTERIOR: &str = "1";
pub const LSG_INTERIOR: &str = "2";
pub const LSG_TRAMLINE: &str = "3";
pub const LSG_GUIDANCE_PATTERN: &str = "5";
/// `PNT` types: other, guidance reference A and B.
const PNT_OTHER: &str = "2";
const PNT_GUIDANCE_A: &str = "6";
const PNT_GUIDANCE_B: &str = "7";
/// `GPN` types AB, A+ and curve.
const GPN_AB: &str = "1";
const GPN_A_PLUS: &str = "2";
const GPN_CURVE: &str = "3";
/// Propagation: none (each swath and pass is its own pattern).
const PROPAGATE_NONE: &str = "4";
const PROPAGATE_BOTH: &str = "1";

impl Exporter for TaskData {
    fn format(&self) -> &'static Format {
        &Format {
            id: "isoxml",
            label: "Tractor terminal (ISOXML TaskData)",
            media_type: "application/zip",
            extension: "-taskdata.zip",
            one_flight_per_file: false,
            firmware_commands: false,
            plans: COVERAGE_ONLY,
            verbatim: false,
            waypoint_limit: false,
            default_max_waypoints: None,
        }
    }
    fn write(&self, job: &ExportJob<'_>, _sortie: usize) -> Result<Vec<Vec<u8>>, InputError> {
        Ok(vec![archive::zip(&[("TASKDATA/TASKDATA.XML".to_owned(), task_data(job))])])
    }
}

/// A sweep line `[lon, lat]` from start to end.
type Line = [[f64; 2]; 2];

fn task_data(job: &ExportJob<'_>) -> Vec<u8> {
    let mut x = root();
    let mut ids = Ids::default();
    let partfields = partfields(&mut x, job, job.name, &mut ids);
    for (k, pfd) in partfields.iter().enumerate() {
        x.empty("TSK", &[("A", &format!("TSK{}", k + 1)), ("B", &format!("Coverage {}", k + 1)), ("E", pfd), ("G", "1")]);
    }
    x.close("ISO11783_TaskData");
    x.finish()
}

/// The document's root element, open.
fn root() -> Xml {
    let mut x = Xml::new();
    x.open(
        "ISO11783_TaskData",
        &[
            ("VersionMajor", "4"),
            ("VersionMinor", "3"),
            ("ManagementSoftwareManufacturer", "coverplan"),
            ("ManagementSoftwareVersion", env!("CARGO_PKG_VERSION")),
            ("DataTransferOrigin", "1"),
        ],
    );
    x
}

/// The last ids given to partfields, guidance groups and patterns (each kind numbered from 1
/// through the document).
#[derive(Default)]
struct Ids {
    partfield: usize,
    group: usize,
    pattern: usize,
}

/// Writes the partfields of a plan's fields, named after `name`; returns their ids.
fn partfields(x: &mut Xml, job: &ExportJob<'_>, name: &str, ids: &mut Ids) -> Vec<String> {
    let fields = &job.outlines.fields.0;
    let field_of = |p: Point| fields.iter().position(|f| f.contains(&p)).unwrap_or(0);
    // each sweep's two ends, and whether it is a tramline
    let sweeps: Vec<(Line, bool)> = job
        .flight
        .sorties
        .iter()
        .flatten()
        .filter(|p| p.kind == PieceKind::Sweep)
        .map(|p| {
            let (a, b) = (p.points[0], p.points[p.points.len() - 1]);
            ([[a[0], a[1]], [b[0], b[1]]], p.tramline)
        })
        .collect();
    let lines: Vec<Line> = sweeps.iter().map(|s| s.0).collect();
    let tramlines: Vec<Line> = sweeps.iter().filter(|s| s.1).map(|s| s.0).collect();
    let passes: Vec<Vec<[f64; 2]>> =
        job.flight.sorties.iter().flatten().filter(|p| p.kind == PieceKind::Headland).map(|p| p.points.iter().map(|q| [q[0], q[1]]).collect()).collect();
    let width_mm = (job.settings.line_spacing_m * 1000.0).round().to_string();
    let mut written = Vec::new();
    for (k, field) in fields.iter().enumerate() {
        ids.partfield += 1;
        let id = format!("PFD{}", ids.partfield);
        let area = field.geodesic_area_unsigned().round().to_string();
        let designator = if fields.len() == 1 { name.to_owned() } else { format!("{name} {}", k + 1) };
        x.open("PFD", &[("A", &id), ("C", &designator), ("D", &area)]);
        x.open("PLN", &[("A", PLN_PARTFIELD_BOUNDARY), ("B", "Boundary")]);
        ring(x, LSG_EXTERIOR, field.exterior());
        for hole in field.interiors() {
            ring(x, LSG_INTERIOR, hole);
        }
        x.close("PLN");
        for (z, zone) in job.outlines.no_fly_zones.0.iter().enumerate() {
            if zone.centroid().map_or(k, field_of) == k {
                x.open("PLN", &[("A", PLN_OBSTACLE), ("B", &format!("No-fly zone {}", z + 1))]);
                ring(x, LSG_EXTERIOR, zone.exterior());
                x.close("PLN");
            }
        }
        let in_field = |l: &&Line| field_of(Point::new((l[0][0] + l[1][0]) / 2.0, (l[0][1] + l[1][1]) / 2.0)) == k;
        for (t, line) in tramlines.iter().filter(in_field).enumerate() {
            x.open("LSG", &[("A", LSG_TRAMLINE), ("B", &format!("Tramline {}", t + 1)), ("C", &width_mm)]);
            for &p in line {
                point(x, PNT_OTHER, p);
            }
            x.close("LSG");
        }
        let mine: Vec<Line> = lines.iter().filter(in_field).copied().collect();
        for (bearing, swaths) in by_direction(&mine) {
            ids.group += 1;
            x.open("GGP", &[("A", &format!("GGP{}", ids.group)), ("B", &format!("Sweep lines {}°", number(bearing, 1)))]);
            // the longest swath: a terminal takes its direction from the two points
            let length = |l: &Line| ((l[1][0] - l[0][0]) * l[0][1].to_radians().cos()).hypot(l[1][1] - l[0][1]);
            let reference = *swaths.iter().max_by(|x, y| length(x).total_cmp(&length(y))).expect("a group has a swath");
            let count = (swaths.len() - 1).to_string();
            ids.pattern += 1;
            let heading = number(bearing, 2);
            let attributes = [("C", GPN_AB), ("E", PROPAGATE_BOTH), ("G", heading.as_str()), ("N", count.as_str()), ("O", count.as_str())];
            guidance(x, ids.pattern, "AB reference", &attributes, &reference, &width_mm);
            for (s, swath) in swaths.iter().enumerate() {
                ids.pattern += 1;
                guidance(x, ids.pattern, &format!("Swath {}", s + 1), &[("C", GPN_AB), ("E", PROPAGATE_NONE), ("G", heading.as_str())], swath, &width_mm);
            }
            x.close("GGP");
        }
        if let Some(g) = job.settings.guidance {
            ids.group += 1;
            ids.pattern += 1;
            x.open("GGP", &[("A", &format!("GGP{}", ids.group)), ("B", "Guidance line")]);
            match (g.b, g.bearing_deg) {
                (Some(b), _) => guidance(x, ids.pattern, "AB line", &[("C", GPN_AB), ("E", PROPAGATE_BOTH)], &[g.a, b], &width_mm),
                (None, bearing) => {
                    let heading = number(bearing.unwrap_or(0.0), 6);
                    guidance(x, ids.pattern, "A+ line", &[("C", GPN_A_PLUS), ("E", PROPAGATE_BOTH), ("G", heading.as_str())], &[g.a], &width_mm)
                }
            }
            x.close("GGP");
        }
        let mine: Vec<&Vec<[f64; 2]>> = passes.iter().filter(|p| field_of(Point::new(p[0][0], p[0][1])) == k).collect();
        if !mine.is_empty() {
            ids.group += 1;
            x.open("GGP", &[("A", &format!("GGP{}", ids.group)), ("B", "Headland passes")]);
            for (s, pass) in mine.iter().enumerate() {
                ids.pattern += 1;
                guidance(x, ids.pattern, &format!("Headland pass {}", s + 1), &[("C", GPN_CURVE), ("E", PROPAGATE_NONE)], pass, &width_mm);
            }
            x.close("GGP");
        }
        x.close("PFD");
        written.push(id);
    }
    written
}

/// A whole farm's TaskData: each field's partfields as its plan's own file writes them, then a
/// task for each stretch of a machine's day on one field, in the schedule's order, named by the
/// machine, the day and the field.
pub struct FarmTaskData {
    x: Xml,
    ids: Ids,
    /// Each field added: its partfields.
    partfields: Vec<(usize, Vec<String>)>,
}

/// A task of the farm's: what it is called, and the field (as added) it works.
pub struct FarmTask {
    pub designator: String,
    pub field: usize,
}

impl Default for FarmTaskData {
    fn default() -> Self {
        FarmTaskData { x: root(), ids: Ids::default(), partfields: Vec::new() }
    }
}

impl FarmTaskData {
    /// Adds field `field` (any number the tasks will name it by), as its plan `request` says.
    pub fn add(&mut self, field: usize, name: &str, request: &ExportRequest<'_>) -> Result<(), InputError> {
        let written = super::with_job(request, TaskData.format(), |job| partfields(&mut self.x, job, name, &mut self.ids))?;
        self.partfields.push((field, written));
        Ok(())
    }

    /// The zip, with a task for each of `tasks` whose field was added (on its first partfield).
    pub fn finish(mut self, tasks: &[FarmTask]) -> Vec<u8> {
        let mut written = 0;
        for task in tasks {
            let Some((_, pfds)) = self.partfields.iter().find(|(f, _)| *f == task.field) else { continue };
            written += 1;
            self.x.empty("TSK", &[("A", &format!("TSK{written}")), ("B", &task.designator), ("E", &pfds[0]), ("G", "1")]);
        }
        self.x.close("ISO11783_TaskData");
        archive::zip(&[("TASKDATA/TASKDATA.XML".to_owned(), self.x.finish())])
    }
}

/// The lines grouped by compass bearing modulo 180° (within half a degree), in order of first
/// appearance, with the group's bearing.
fn by_direction(lines: &[Line]) -> Vec<(f64, Vec<Line>)> {
    let mut groups: Vec<(f64, Vec<Line>)> = Vec::new();
    for line in lines {
        let cos = line[0][1].to_radians().cos();
        let bearing = ((line[1][0] - line[0][0]) * cos).atan2(line[1][1] - line[0][1]).to_degrees().rem_euclid(180.0);
        let near = |b: f64| {
            let d = (b - bearing).rem_euclid(180.0);
            d.min(180.0 - d) < 0.5
        };
        match groups.iter_mut().find(|g| near(g.0)) {
            Some(g) => g.1.push(*line),
            None => groups.push((bearing, vec![*line])),
        }
    }
    groups
}

/// A guidance pattern through `points`: the first is its A point, the last (of two or more) its
/// B point.
fn guidance(x: &mut Xml, id: usize, designator: &str, attributes: &[(&str, &str)], points: &[[f64; 2]], width_mm: &str) {
    let id = format!("GPN{id}");
    let mut all = vec![("A", id.as_str()), ("B", designator)];
    all.extend_from_slice(attributes);
    x.open("GPN", &all).open("LSG", &[("A", LSG_GUIDANCE_PATTERN), ("C", width_mm)]);
    for (i, &p) in points.iter().enumerate() {
        let kind = if i == 0 {
            PNT_GUIDANCE_A
        } else if i + 1 == points.len() {
            PNT_GUIDANCE_B
        } else {
            PNT_OTHER
        };
        point(x, kind, p);
    }
    x.close("LSG").close("GPN");
}

/// A ring without its closing point (implicit in ISOXML).
fn ring(x: &mut Xml, kind: &str, ring: &LineString) {
    x.open("LSG", &[("A", kind)]);
    for c in &ring.0[..ring.0.len() - 1] {
        point(x, PNT_OTHER, [c.x, c.y]);
    }
    x.close("LSG");
}

fn point(x: &mut Xml, kind: &str, [lon, lat]: [f64; 2]) {
    x.empty("PNT", &[("A", kind), ("C", &number(lat, 9)), ("D", &number(lon, 9))]);
}
