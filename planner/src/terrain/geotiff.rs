//! GeoTIFF elevation models, read with `tiff`: one band of integer or float samples, placed
//! by ModelPixelScale + ModelTiepoint or by a ModelTransformation without rotation, in the
//! system its GeoKeys name, with GDAL's nodata value.

use std::io::Cursor;

use tiff::decoder::{Decoder, DecodingResult, Limits};
use tiff::tags::Tag;

use super::{Crs, ElevationModel, MAX_CELLS, unsupported};
use crate::error::InputError;

pub fn is_tiff(bytes: &[u8]) -> bool {
    bytes.starts_with(b"II*\0") || bytes.starts_with(b"MM\0*") || bytes.starts_with(b"II+\0") || bytes.starts_with(b"MM\0+")
}

// GeoKey ids (GeoTIFF 1.1, §7)
const MODEL_TYPE: u16 = 1024;
const RASTER_TYPE: u16 = 1025;
const GEOGRAPHIC_TYPE: u16 = 2048;
const PROJECTED_TYPE: u16 = 3072;
const PROJ_LINEAR_UNITS: u16 = 3076;
const USER_DEFINED: u16 = 32767;
const METRE: u16 = 9001;
const PIXEL_IS_POINT: u16 = 2;

fn invalid(detail: impl Into<String>) -> InputError {
    InputError::new("invalid_terrain", "/", detail)
}

pub fn read(bytes: &[u8]) -> Result<ElevationModel, InputError> {
    let broken = |e: tiff::TiffError| invalid(format!("the GeoTIFF cannot be read: {e}"));
    let mut limits = Limits::default();
    limits.decoding_buffer_size = MAX_CELLS * 8;
    let mut tiff = Decoder::new(Cursor::new(bytes)).map_err(broken)?.with_limits(limits);
    let (cols, rows) = tiff.dimensions().map_err(broken)?;
    let (cols, rows) = (cols as usize, rows as usize);
    if cols.saturating_mul(rows) > MAX_CELLS {
        return Err(InputError::new("terrain_too_large", "/", format!("the model has {cols} × {rows} cells; the limit is {MAX_CELLS}: crop it to the fields")));
    }
    if tiff.find_tag_unsigned::<u16>(Tag::SamplesPerPixel).map_err(broken)?.unwrap_or(1) != 1 {
        return Err(invalid("the GeoTIFF has several bands; an elevation model has one (heights)"));
    }
    let keys = geo_keys(&mut tiff)?;
    let key = |id: u16| keys.iter().find(|k| k.0 == id).map(|k| k.1);
    let crs = crs_of(&key)?;
    let point = key(RASTER_TYPE) == Some(PIXEL_IS_POINT);
    let (origin, step) = placement(&mut tiff, point)?;
    let nodata = match tiff.find_tag(Tag::GdalNodata).map_err(broken)? {
        Some(v) => {
            let text = v.into_string().map_err(broken)?;
            let text = text.trim_matches(|c: char| c == '\0' || c.is_whitespace());
            Some(text.parse::<f64>().map_err(|_| invalid(format!("the GeoTIFF's nodata value `{text}` is not a number")))?)
        }
        None => None,
    };
    let samples = tiff.read_image().map_err(broken)?;
    let values: Vec<f64> = match samples {
        DecodingResult::U8(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U16(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::U32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I8(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I16(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::I32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::F32(v) => v.into_iter().map(f64::from).collect(),
        DecodingResult::F64(v) => v,
        _ => return Err(invalid("the GeoTIFF's samples are neither 8 to 32 bit integers nor 32 or 64 bit floats")),
    };
    if values.len() != cols * rows {
        return Err(invalid(format!("the GeoTIFF holds {} samples for {cols} × {rows} cells", values.len())));
    }
    // 32-bit floats carry the nodata value rounded: compare as f32
    let is_nodata = |h: f64| !h.is_finite() || nodata.is_some_and(|n| h as f32 == n as f32);
    let heights = values.into_iter().map(|h| if is_nodata(h) { f32::NAN } else { h as f32 }).collect();
    ElevationModel::new(cols, rows, heights, origin, step, crs)
}

/// The GeoKeys whose value sits in the directory itself: (key, value).
fn geo_keys(tiff: &mut Decoder<Cursor<&[u8]>>) -> Result<Vec<(u16, u16)>, InputError> {
    let directory = tiff
        .find_tag(Tag::GeoKeyDirectoryTag)
        .map_err(|e| invalid(format!("the GeoTIFF's GeoKeys cannot be read: {e}")))?
        .ok_or_else(|| invalid("the TIFF has no GeoKeys: it is an image, not a GeoTIFF placed on the Earth"))?
        .into_u16_vec()
        .map_err(|e| invalid(format!("the GeoTIFF's GeoKeys cannot be read: {e}")))?;
    let count = directory.get(3).copied().unwrap_or(0) as usize;
    Ok(directory[4..].chunks_exact(4).take(count).filter(|k| k[1] == 0).map(|k| (k[0], k[3])).collect())
}

fn crs_of(key: &dyn Fn(u16) -> Option<u16>) -> Result<Crs, InputError> {
    match (key(PROJECTED_TYPE), key(GEOGRAPHIC_TYPE), key(MODEL_TYPE)) {
        (Some(USER_DEFINED), _, _) => Err(unsupported("a user-defined projection", "/")),
        (Some(code), _, _) => {
            if key(PROJ_LINEAR_UNITS).is_some_and(|u| u != METRE) {
                return Err(unsupported(&format!("EPSG:{code} in units other than metres"), "/"));
            }
            Crs::from_epsg(u32::from(code), "/")
        }
        (None, Some(4326), _) => Ok(Crs::LonLat),
        (None, Some(code), _) => Err(unsupported(&format!("EPSG:{code}"), "/")),
        (None, None, Some(1)) => Err(unsupported("a projection without an EPSG code", "/")),
        (None, None, _) => Err(unsupported("not named in the GeoKeys", "/")),
    }
}

/// The centre of cell (0, 0) and the step to the next column and row.
fn placement(tiff: &mut Decoder<Cursor<&[u8]>>, point: bool) -> Result<([f64; 2], [f64; 2]), InputError> {
    let mut f64s = |tag: Tag| -> Result<Option<Vec<f64>>, InputError> {
        let broken = |e: tiff::TiffError| invalid(format!("the GeoTIFF's placement cannot be read: {e}"));
        tiff.find_tag(tag).map_err(broken)?.map(|v| v.into_f64_vec().map_err(broken)).transpose()
    };
    // a cell's value is at its centre; tie points name its corner unless the raster is PixelIsPoint
    let centre = if point { 0.0 } else { 0.5 };
    if let (Some(scale), Some(tie)) = (f64s(Tag::ModelPixelScaleTag)?, f64s(Tag::ModelTiepointTag)?) {
        let ([sx, sy], [i, j, _, x, y]) =
            ([scale.first().copied().unwrap_or(f64::NAN), scale.get(1).copied().unwrap_or(f64::NAN)], [0, 1, 2, 3, 4].map(|k| tie.get(k).copied().unwrap_or(f64::NAN)));
        // pixel scale is positive with rows running south (GeoTIFF §2.6.1)
        return Ok(([x + (centre - i) * sx, y - (centre - j) * sy], [sx, -sy]));
    }
    if let Some(m) = f64s(Tag::ModelTransformationTag)? {
        if m.len() < 8 || m[1] != 0.0 || m[4] != 0.0 {
            return Err(invalid("the GeoTIFF's ModelTransformation rotates the raster; give it north-up (gdalwarp)"));
        }
        return Ok(([m[3] + centre * m[0], m[7] + centre * m[5]], [m[0], m[5]]));
    }
    Err(invalid("the GeoTIFF has neither ModelPixelScale and ModelTiepoint nor ModelTransformation: it is not placed"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fixture(name: &str) -> Vec<u8> {
        std::fs::read(format!("{}/../tests/fixtures/terrain/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap()
    }

    #[test]
    fn reads_the_test_models() {
        // (file, EPSG, columns, rows, lowest, highest)
        for (name, epsg, cols, rows, lo, hi) in
            [("jacksboro.tif", "EPSG:4326", 403, 344, 236.0, 1076.0), ("hills-11.tif", "EPSG:32632", 260, 240, 250.0, 600.0), ("cliff-11.tif", "EPSG:32617", 300, 300, 0.0, 2000.0)]
        {
            let model = ElevationModel::read(&fixture(name), name).unwrap();
            let s = model.summary();
            assert_eq!((s.crs.as_str(), s.columns, s.rows), (epsg, cols, rows), "{name}");
            assert!(s.min_m >= lo && s.max_m <= hi && s.max_m > s.min_m, "{name}: {s:?}");
        }
        let jacksboro = ElevationModel::read(&fixture("jacksboro.tif"), "jacksboro.tif").unwrap().summary();
        assert_eq!((jacksboro.min_m, jacksboro.max_m), (236.0, 1076.0));
    }

    #[test]
    fn the_test_fields_lie_on_their_models() {
        for name in ["jacksboro", "hills-11", "ridge-11", "cliff-11"] {
            let mission: serde_json::Value = serde_json::from_slice(&fixture(&format!("{name}.json"))).unwrap();
            let model = ElevationModel::read(&fixture(&format!("{name}.tif")), "x.tif").unwrap();
            for p in mission["area"]["coordinates"][0].as_array().unwrap() {
                let h = model.height_at(p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
                assert!(h.is_some(), "{name}: {p}");
            }
        }
    }
}
