//! ISO 11783-10 TaskData (a zip with `TASKDATA/TASKDATA.XML`, or the XML alone), read with
//! quick-xml: each partfield's boundary polygon (`PLN` type 1) is a field with its interior rings
//! as holes; obstacle polygons (type 6) are no-fly zones; water and buildings (types 3 and 4) are
//! holes of the field they lie in. The closing point of a ring may be given or not.

use geo::{Contains, LineString, Polygon};
use quick_xml::Reader;
use quick_xml::events::{BytesStart, Event};

use super::{Collected, Glimpse, Importer, Kind, ring};
use crate::archive;
use crate::error::InputError;

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
            b"PNT" => {
                if let Some((_, points)) = line.as_mut() {
                    points.push([coordinate(e, b"D", &at)?, coordinate(e, b"C", &at)?]);
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
            out.add(Kind::Field, Polygon::new(exterior, interiors), None, at);
        }
        "6" => out.add(Kind::NoFlyZone, Polygon::new(exterior, interiors), None, at),
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
            <GGP A="GGP1"><GPN A="GPN1" C="1"><LSG A="5"><PNT A="6" C="47.1" D="8.1"/><PNT A="7" C="47.2" D="8.2"/></LSG></GPN></GGP>
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
    }
}
