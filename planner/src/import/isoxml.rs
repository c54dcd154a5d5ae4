//! ISO 11783-10 TaskData (a zip with `TASKDATA/TASKDATA.XML`, or the XML alone), read with
//! quick-xml: each partfield's boundary polygon (`PLN` type 1) is a field with its interior rings
//! as holes; obstacle polygons (type 6) are no-fly zones; water and buildings (types 3 and 4) are
//! holes of the field they lie in. The closing point of a ring may be given or not. Guidance
//! patterns (`GPN`) of type AB and A+ that propagate to neighbouring swaths are the farm's
//! guidance lines; curves, pivots and spirals are reported and left out.

use geo::{Contains, LineString, Polygon};
use quick_xml::Reader;
use quick_xml::events::{BytesStart, Event};

use super::{Collected, Glimpse, ImportedGuidance, Importer, Kind, ring};
use crate::archive;
use crate::error::InputError;
use crate::params::guidance::Guidance;

pub struct TaskData;

impl Importer for TaskData {
    fn id(&self) -> &'static str {
        "isoxml"
    }
    fn recognises(&self, glimpse: &Glimpse<'_>) -> bool {
        glimpse.zip_holds("taskdata.xml") || matches!(glimpse, Glimpse::Xml(head) if head.contains("ISO11783_TaskData"))
    }

    fn read(&self, bytes: &[u8]) -> Result<Collected, InputError> {
        if !archive::is_zip(bytes) {
            return read_xml(bytes, "/TASKDATA.XML");
        }
        let files = archive::unzip(bytes)?;
        let (name, xml) = files
            .iter()
            .find(|(n, _)| n.to_ascii_uppercase().ends_with("TASKDATA.XML"))
            .ok_or_else(|| InputError::new("missing_file_part", "/TASKDATA/TASKDATA.XML", "the zip holds no TASKDATA.XML"))?;
        read_xml(xml, &format!("/{name}"))
    }
}

/// A guidance pattern being read: its type, name, heading, whether it propagates, and its
/// points (type, position).
struct OpenPattern {
    kind: String,
    designator: String,
    heading: Option<String>,
    propagates: bool,
    points: Vec<(String, [f64; 2])>,
}

/// `GPN` types (ISO 11783-10): AB, A+.
const GPN_AB: &str = "1";
const GPN_A_PLUS: &str = "2";
/// `GPN` propagation: none (a single track, not a guidance line).
const PROPAGATES_NOT: &str = "4";
/// `PNT` types: guidance reference A and B.
const PNT_A: &str = "6";
const PNT_B: &str = "7";

/// A polygon element being read: its type and rings (type, points).
#[derive(Default)]
struct OpenPolygon {
    kind: String,
    designator: String,
    rings: Vec<(String, Vec<[f64; 2]>)>,
}

fn attribute(e: &BytesStart<'_>, name: &[u8], at: &str) -> Result<Option<String>, InputError> {
    for a in e.attributes() {
        let a = a.map_err(|err| InputError::new("invalid_xml", at, format!("unreadable attribute: {err}")))?;
        if a.key.as_ref() == name {
            let v = a.normalized_value(quick_xml::XmlVersion::Implicit1_0).map_err(|err| InputError::new("invalid_xml", at, format!("unreadable attribute: {err}")))?;
            return Ok(Some(v.into_owned()));
        }
    }
    Ok(None)
}

fn coordinate(e: &BytesStart<'_>, name: &[u8], at: &str) -> Result<f64, InputError> {
    let text = attribute(e, name, at)?.ok_or_else(|| InputError::new("invalid_isoxml", at, format!("a PNT without its {} attribute", String::from_utf8_lossy(name))))?;
    text.trim().parse().map_err(|_| InputError::new("invalid_isoxml", at, format!("`{text}` is not a coordinate")))
}

fn read_xml(bytes: &[u8], part: &str) -> Result<Collected, InputError> {
    let text = archive::xml_text(bytes, part)?;
    let mut reader = Reader::from_str(text);
    let mut out = Collected::default();
    let mut polygon: Option<OpenPolygon> = None;
    let mut line: Option<(String, Vec<[f64; 2]>)> = None;
    let mut pattern: Option<OpenPattern> = None;
    let mut partfield = String::new();
    let mut holes_to_place: Vec<LineString> = Vec::new();
    let mut seen_root = false;
    loop {
        let at = format!("{part}@{}", reader.buffer_position());
        let event = reader.read_event().map_err(|e| InputError::new("invalid_xml", &at, format!("not well-formed XML: {e}")))?;
        let (e, closes) = match &event {
            Event::Start(e) => (Some(e), false),
            Event::Empty(e) => (Some(e), true),
            Event::End(end) => {
                match end.name().as_ref() {
                    b"LSG" => {
                        if let (Some(p), Some(l)) = (polygon.as_mut(), line.take()) {
                            p.rings.push(l);
                        }
                    }
                    b"PLN" => {
                        if let Some(p) = polygon.take() {
                            close_polygon(p, &partfield, &at, &mut out, &mut holes_to_place)?;
                        }
                    }
                    b"GPN" => {
                        if let Some(p) = pattern.take() {
                            close_pattern(p, &at, &mut out);
                        }
                    }
                    _ => {}
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let Some(e) = e else { continue };
        match e.name().as_ref() {
            b"ISO11783_TaskData" => seen_root = true,
            b"PFD" => partfield = attribute(e, b"C", &at)?.unwrap_or_default(),
            b"XFR" => out.warnings.push(format!("{at}: external TaskData files (XFR) are not read")),
            b"PLN" if !closes => {
                polygon = Some(OpenPolygon { kind: attribute(e, b"A", &at)?.unwrap_or_default(), designator: attribute(e, b"B", &at)?.unwrap_or_default(), rings: vec![] })
            }
            b"LSG" if polygon.is_some() && !closes => line = Some((attribute(e, b"A", &at)?.unwrap_or_default(), Vec::new())),
            b"GPN" if !closes && polygon.is_none() => {
                pattern = Some(OpenPattern {
                    kind: attribute(e, b"C", &at)?.unwrap_or_default(),
                    designator: attribute(e, b"B", &at)?.or(attribute(e, b"A", &at)?).unwrap_or_default(),
                    heading: attribute(e, b"G", &at)?,
                    propagates: attribute(e, b"E", &at)?.as_deref() != Some(PROPAGATES_NOT),
                    points: Vec::new(),
                })
            }
            b"PNT" => {
                if let Some((_, points)) = line.as_mut() {
                    points.push([coordinate(e, b"D", &at)?, coordinate(e, b"C", &at)?]);
                } else if let Some(p) = pattern.as_mut() {
                    p.points.push((attribute(e, b"A", &at)?.unwrap_or_default(), [coordinate(e, b"D", &at)?, coordinate(e, b"C", &at)?]));
                }
            }
            _ => {}
        }
    }
    if !seen_root {
        return Err(InputError::new("invalid_isoxml", part, "the root element is not ISO11783_TaskData"));
    }
    for hole in holes_to_place {
        let inside = Polygon::new(hole.clone(), vec![]);
        match out.fields.iter_mut().find(|f| f.contains(&inside)) {
            Some(f) => f.interiors_push(hole),
            None => out.warnings.push(format!("{part}: a water or building polygon outside every field was dropped")),
        }
    }
    Ok(out)
}

/// Files a finished `GPN` of type AB or A+ as a guidance line; a single track (no propagation)
/// is passed over, other types and lines without a direction are reported.
fn close_pattern(p: OpenPattern, at: &str, out: &mut Collected) {
    if !p.propagates {
        return;
    }
    let find = |kind: &str| p.points.iter().find(|(k, _)| k == kind).map(|(_, q)| *q);
    let (first, last) = (p.points.first().map(|q| q.1), p.points.last().map(|q| q.1));
    let name = p.designator;
    let guidance = match p.kind.as_str() {
        GPN_AB => match (find(PNT_A).or(first), find(PNT_B).or(last)) {
            (Some(a), Some(b)) if p.points.len() >= 2 => Ok(Guidance { a, b: Some(b), bearing_deg: None }),
            _ => Err("has no points A and B".to_owned()),
        },
        GPN_A_PLUS => {
            let heading = p.heading.as_deref().and_then(|h| h.trim().parse::<f64>().ok());
            match (find(PNT_A).or(first), heading) {
                (Some(a), Some(h)) => Ok(Guidance { a, b: None, bearing_deg: Some(h) }),
                _ => Err("needs a point A and a heading (G)".to_owned()),
            }
        }
        other => Err(format!("of type {other} was left out (AB and A+ lines are read)")),
    };
    // a line without a direction is left out with the reason: the rest of the file stands
    match guidance.and_then(|g| g.validate().map(|_| g).map_err(|e| format!("was left out: {}", e.detail))) {
        Ok(guidance) => out.guidance.push(ImportedGuidance { name, guidance }),
        Err(why) => out.warnings.push(format!("{at}: guidance pattern `{name}` {why}")),
    }
}

/// Files a finished `PLN` as a field, a no-fly zone, a hole to place, or a dropped polygon.
fn close_polygon(p: OpenPolygon, partfield: &str, at: &str, out: &mut Collected, holes: &mut Vec<LineString>) -> Result<(), InputError> {
    let mut exterior = None;
    let mut interiors = Vec::new();
    for (kind, points) in p.rings {
        let r = ring(points, at)?;
        match kind.as_str() {
            "1" if exterior.is_none() => exterior = Some(r),
            "1" | "2" => interiors.push(r),
            other => out.warnings.push(format!("{at}: a line string of type {other} in a polygon was dropped")),
        }
    }
    let Some(exterior) = exterior else {
        out.warnings.push(format!("{at}: polygon `{}` has no exterior ring and was dropped", p.designator));
        return Ok(());
    };
    match p.kind.as_str() {
        "1" => {
            if out.name.is_none() && !partfield.is_empty() {
                out.name = Some(partfield.to_owned());
            }
            out.add(Kind::Field, Polygon::new(exterior, interiors), None, Some(partfield), at);
        }
        "6" => out.add(Kind::NoFlyZone, Polygon::new(exterior, interiors), None, None, at),
        "3" | "4" => holes.push(exterior),
        other => out.warnings.push(format!("{at}: polygon `{}` of type {other} was dropped (boundaries, obstacles, water and buildings are read)", p.designator)),
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const PNT: &str = r#"<PNT A="2" C="{lat}" D="{lon}"/>"#;

    fn ring(points: &[[f64; 2]], closed: bool) -> String {
        let mut all: Vec<[f64; 2]> = points.to_vec();
        if closed {
            all.push(points[0]);
        }
        all.iter().map(|[lon, lat]| PNT.replace("{lat}", &lat.to_string()).replace("{lon}", &lon.to_string())).collect()
    }

    #[test]
    fn boundaries_holes_obstacles_and_buildings() {
        let square = |x: f64, y: f64, d: f64| [[x, y], [x + d, y], [x + d, y + d], [x, y + d]];
        let xml = format!(
            r#"<?xml version="1.0"?><ISO11783_TaskData VersionMajor="3"><PFD A="PFD1" C="Big field" D="1">
            <PLN A="1"><LSG A="1">{}</LSG><LSG A="2">{}</LSG></PLN>
            <PLN A="6" B="Mast"><LSG A="1">{}</LSG></PLN>
            <PLN A="4" B="Barn"><LSG A="1">{}</LSG></PLN>
            <PLN A="10" B="Headland"><LSG A="1">{}</LSG></PLN>
            <GGP A="GGP1"><GPN A="GPN1" C="1"><LSG A="5"><PNT A="6" C="47.1" D="8.1"/><PNT A="7" C="47.2" D="8.2"/></LSG></GPN>
            <GPN A="GPN2" B="Tramlines" C="2" G="12.34"><LSG A="5"><PNT A="6" C="47.05" D="8.05"/></LSG></GPN>
            <GPN A="GPN3" B="Swath 1" C="1" E="4"><LSG A="5"><PNT A="6" C="47.0" D="8.0"/><PNT A="7" C="47.1" D="8.0"/></LSG></GPN>
            <GPN A="GPN4" B="Creek" C="3"><LSG A="5"><PNT A="6" C="47.0" D="8.0"/><PNT A="9" C="47.01" D="8.02"/><PNT A="7" C="47.1" D="8.0"/></LSG></GPN></GGP>
            </PFD></ISO11783_TaskData>"#,
            ring(&square(8.0, 47.0, 0.1), false),
            ring(&square(8.01, 47.01, 0.01), true),
            ring(&square(8.05, 47.05, 0.01), false),
            ring(&square(8.07, 47.07, 0.01), true),
            ring(&square(8.0, 47.0, 0.1), false),
        );
        let out = TaskData.read(xml.as_bytes()).unwrap();
        assert_eq!(out.name.as_deref(), Some("Big field"));
        assert_eq!(out.fields.len(), 1);
        assert_eq!(out.fields[0].interiors().len(), 2, "the hole and the barn");
        assert_eq!(out.fields[0].exterior().0.len(), 5, "closed once");
        assert_eq!(out.no_fly_zones.len(), 1);
        assert!(out.warnings.iter().any(|w| w.contains("type 10")), "{:?}", out.warnings);
        // the AB and the A+ line; a single swath's track is passed over, the curve reported
        let lines: Vec<(&str, Guidance)> = out.guidance.iter().map(|g| (g.name.as_str(), g.guidance)).collect();
        assert_eq!(
            lines,
            vec![("GPN1", Guidance { a: [8.1, 47.1], b: Some([8.2, 47.2]), bearing_deg: None }), ("Tramlines", Guidance { a: [8.05, 47.05], b: None, bearing_deg: Some(12.34) })]
        );
        assert!(out.warnings.iter().any(|w| w.contains("`Creek` of type 3")), "{:?}", out.warnings);
    }

    #[test]
    fn guidance_patterns_without_a_direction_are_left_out_with_the_reason() {
        let file = |pattern: &str| format!(r#"<ISO11783_TaskData><PFD A="PFD1" C="f" D="1"><GGP A="GGP1">{pattern}</GGP></PFD></ISO11783_TaskData>"#);
        let a_plus = file(r#"<GPN A="GPN1" B="Old line" C="2"><LSG A="5"><PNT A="6" C="47.05" D="8.05"/></LSG></GPN>"#);
        let out = TaskData.read(a_plus.as_bytes()).unwrap();
        assert!(out.guidance.is_empty() && out.warnings.iter().any(|w| w.contains("`Old line` needs a point A and a heading")), "{:?}", out.warnings);
        let same_points = file(r#"<GPN A="GPN1" B="Dot" C="1"><LSG A="5"><PNT A="6" C="47.05" D="8.05"/><PNT A="7" C="47.05" D="8.05"/></LSG></GPN>"#);
        let out = TaskData.read(same_points.as_bytes()).unwrap();
        assert!(out.guidance.is_empty() && out.warnings.iter().any(|w| w.contains("`Dot` was left out") && w.contains("give no direction")), "{:?}", out.warnings);
    }
}
