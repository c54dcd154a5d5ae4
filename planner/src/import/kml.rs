//! KML and KMZ (read with the `kml` crate): Polygon and MultiGeometry placemarks. A placemark
//! whose name or `kind` data says no-fly zone or obstacle becomes one; a polygon that lies inside
//! a field becomes a hole of it; a Point named home becomes home; lines are dropped.

use geo::{Contains, LineString, Polygon};
use kml::types::{Element, Geometry, LinearRing, Placemark};
use kml::{Kml as Doc, KmlReader};

use super::{Collected, Glimpse, Importer, Kind, kind_of_label, ring};
use crate::archive;
use crate::error::InputError;

pub struct Kml;
pub struct Kmz;

impl Importer for Kml {
    fn id(&self) -> &'static str {
        "kml"
    }
    fn recognises(&self, glimpse: &Glimpse<'_>) -> bool {
        matches!(glimpse, Glimpse::Xml(_))
    }
    fn read(&self, bytes: &[u8]) -> Result<Collected, InputError> {
        read_kml(bytes, "/doc.kml")
    }
}

impl Importer for Kmz {
    fn id(&self) -> &'static str {
        "kmz"
    }
    fn recognises(&self, glimpse: &Glimpse<'_>) -> bool {
        glimpse.zip_holds(".kml")
    }
    fn read(&self, bytes: &[u8]) -> Result<Collected, InputError> {
        if !archive::is_zip(bytes) {
            return Err(InputError::new("invalid_zip", "/", "a KMZ file is a zip archive; this is not one"));
        }
        let files = archive::unzip(bytes)?;
        // the main document is doc.kml by convention, else the first .kml at the top
        let main = files.iter().find(|(n, _)| n.eq_ignore_ascii_case("doc.kml")).or_else(|| files.iter().find(|(n, _)| n.to_ascii_lowercase().ends_with(".kml")));
        let (name, content) = main.ok_or_else(|| InputError::new("missing_file_part", "/doc.kml", "the KMZ holds no .kml document"))?;
        read_kml(content, &format!("/{name}"))
    }
}

/// Placemarks found, with the number dropped by kind of geometry.
struct Walk {
    out: Collected,
    dropped_lines: usize,
    dropped_points: usize,
}

fn read_kml(bytes: &[u8], part: &str) -> Result<Collected, InputError> {
    let text = archive::xml_text(bytes, part)?;
    let doc: Doc<f64> = KmlReader::<_, f64>::from_string(text).read().map_err(|e| InputError::new("invalid_kml", part, format!("not readable KML: {e}")))?;
    let mut walk = Walk { out: Collected::default(), dropped_lines: 0, dropped_points: 0 };
    visit(&doc, part, &mut walk)?;
    let mut out = walk.out;
    if walk.dropped_lines > 0 {
        out.warnings.push(format!("{part}: {} line strings were dropped (only polygons and a home point are read)", walk.dropped_lines));
    }
    if walk.dropped_points > 0 {
        out.warnings.push(format!("{part}: {} points other than home were dropped", walk.dropped_points));
    }
    nest_holes(&mut out);
    Ok(out)
}

fn visit(node: &Doc<f64>, part: &str, walk: &mut Walk) -> Result<(), InputError> {
    match node {
        Doc::KmlDocument(d) => d.elements.iter().try_for_each(|e| visit(e, part, walk)),
        Doc::Document { elements, .. } => {
            // the document's own name names the mission
            let named = elements.iter().find_map(|e| match e {
                Doc::Element(el) if el.name == "name" => el.content.as_deref().map(str::trim).filter(|n| !n.is_empty()),
                _ => None,
            });
            if let Some(name) = named.filter(|_| walk.out.name.is_none()) {
                walk.out.name = Some(name.to_owned());
            }
            elements.iter().try_for_each(|e| visit(e, part, walk))
        }
        Doc::Folder(f) => f.elements.iter().try_for_each(|e| visit(e, part, walk)),
        Doc::Placemark(p) => placemark(p, part, walk),
        Doc::Polygon(p) => {
            let polygon = polygon(p, part)?;
            walk.out.add(Kind::Field, polygon, None, None, part);
            Ok(())
        }
        _ => Ok(()),
    }
}

/// The placemark's `<Data name="key"><value>…</value></Data>` entries.
fn data<'a>(p: &'a Placemark<f64>, key: &str) -> Option<&'a str> {
    fn find<'a>(e: &'a Element, key: &str) -> Option<&'a str> {
        if e.name == "Data" && e.attrs.get("name").is_some_and(|n| n == key) {
            return e.children.iter().find(|c| c.name == "value").and_then(|v| v.content.as_deref());
        }
        e.children.iter().find_map(|c| find(c, key))
    }
    p.children.iter().find_map(|e| find(e, key))
}

fn placemark(p: &Placemark<f64>, part: &str, walk: &mut Walk) -> Result<(), InputError> {
    let name = p.name.clone().unwrap_or_default();
    let at = format!("{part}/Placemark[{name}]");
    let label = format!("{name} {} {}", data(p, "kind").unwrap_or_default(), p.style_url.as_deref().unwrap_or_default());
    let kind = kind_of_label(&label).unwrap_or(Kind::Field);
    // without a document name, the first field's placemark names the mission
    if kind == Kind::Field && walk.out.name.is_none() && !name.trim().is_empty() && matches!(&p.geometry, Some(Geometry::Polygon(_) | Geometry::MultiGeometry(_))) {
        walk.out.name = Some(name.trim().to_owned());
    }
    let height = data(p, "height_m").and_then(|h| h.trim().parse::<f64>().ok());
    let Some(geometry) = &p.geometry else { return Ok(()) };
    let mut geometries = vec![geometry];
    while let Some(g) = geometries.pop() {
        match g {
            Geometry::Polygon(poly) => walk.out.add(kind, polygon(poly, &at)?, height, Some(name.as_str()), &at),
            Geometry::MultiGeometry(m) => geometries.extend(m.geometries.iter().rev()),
            Geometry::Point(pt) if name.to_ascii_lowercase().contains("home") => walk.out.home = Some([pt.coord.x, pt.coord.y]),
            Geometry::Point(_) => walk.dropped_points += 1,
            _ => walk.dropped_lines += 1,
        }
    }
    Ok(())
}

fn polygon(p: &kml::types::Polygon<f64>, at: &str) -> Result<Polygon, InputError> {
    let to_ring = |r: &LinearRing<f64>| -> Result<LineString, InputError> { ring(r.coords.iter().map(|c| [c.x, c.y]).collect(), at) };
    Ok(Polygon::new(to_ring(&p.outer)?, p.inner.iter().map(to_ring).collect::<Result<_, _>>()?))
}

/// Fields that lie inside another field become its holes (KML tools often draw holes as
/// separate polygons).
fn nest_holes(out: &mut Collected) {
    let mut fields = std::mem::take(&mut out.fields);
    let mut k = 0;
    while k < fields.len() {
        match (0..fields.len()).find(|&o| o != k && fields[o].contains(&fields[k])) {
            Some(outer) => {
                let hole = fields.remove(k);
                let outer = if outer > k { outer - 1 } else { outer };
                fields[outer].interiors_push(hole.exterior().clone());
                k = 0;
            }
            None => k += 1,
        }
    }
    out.fields = fields;
}
