//! SRTM `.hgt` tiles: a square of big-endian 16-bit heights, 1201 (3″) or 3601 (1″) a side,
//! row 0 at the tile's north edge; the file name (`N36W084.hgt`) gives its south-west corner.
//! −32 768 marks a void.

use super::{Crs, ElevationModel};
use crate::error::InputError;

const VOID: i16 = i16::MIN;

/// The side of a tile of `len` bytes.
pub fn side(len: usize) -> Option<usize> {
    [1201, 3601].into_iter().find(|n| n * n * 2 == len)
}

pub fn read(bytes: &[u8], file_name: &str) -> Result<ElevationModel, InputError> {
    let n = side(bytes.len())
        .ok_or_else(|| InputError::new("invalid_terrain", "/", format!("an SRTM .hgt tile is 1201 × 1201 or 3601 × 3601 heights; this one is {} bytes", bytes.len())))?;
    let [lon, lat] = corner(file_name)?;
    let heights = bytes.chunks_exact(2).map(|b| i16::from_be_bytes([b[0], b[1]])).map(|h| if h == VOID { f32::NAN } else { f32::from(h) }).collect();
    let step = 1.0 / (n - 1) as f64;
    // samples sit on the grid lines: the first is the tile's north-west corner
    ElevationModel::new(n, n, heights, [lon, lat + 1.0], [step, -step], Crs::LonLat)
}

/// `N36W084` (any case, any extension) → `[-84, 36]`.
fn corner(file_name: &str) -> Result<[f64; 2], InputError> {
    let base = file_name.rsplit(['/', '\\']).next().unwrap_or(file_name).to_ascii_uppercase();
    let bad = || {
        InputError::new(
            "invalid_terrain",
            "/",
            format!("an SRTM tile's name gives its place, as N36W084.hgt; `{file_name}` does not: upload it under its original name (or zipped)"),
        )
    };
    let b = base.as_bytes();
    if b.len() < 7 || !matches!(b[0], b'N' | b'S') || !matches!(b[3], b'E' | b'W') {
        return Err(bad());
    }
    let lat: f64 = base[1..3].parse().map_err(|_| bad())?;
    let lon: f64 = base[4..7].parse().map_err(|_| bad())?;
    let lat = if b[0] == b'S' { -lat } else { lat };
    let lon = if b[3] == b'W' { -lon } else { lon };
    if !(-90.0..90.0).contains(&lat) || !(-180.0..180.0).contains(&lon) {
        return Err(bad());
    }
    Ok([lon, lat])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::archive;

    fn tile(f: impl Fn(usize, usize) -> i16) -> Vec<u8> {
        (0..1201).flat_map(|r| (0..1201).map(move |c| (r, c))).flat_map(|(r, c)| f(r, c).to_be_bytes()).collect()
    }

    #[test]
    fn reads_a_tile_by_its_name_plain_or_zipped() {
        // heights rise 1 m per column eastwards; a void in the south-east corner
        let bytes = tile(|r, c| if r > 1190 && c > 1190 { VOID } else { c as i16 });
        let model = ElevationModel::read(&bytes, "N36W084.hgt").unwrap();
        let h = model.height_at(-84.0 + 600.5 / 1200.0, 36.5).unwrap();
        assert!((h - 600.5).abs() < 1e-6, "{h}");
        assert_eq!(model.height_at(-83.001, 36.001), None);
        assert_eq!(model.summary().nodata_cells, 100);
        let zipped = archive::zip(&[("S12E130.hgt".into(), bytes)]);
        let south = ElevationModel::read(&zipped, "tile.zip").unwrap();
        assert!(south.height_at(130.5, -11.5).is_some() && south.height_at(130.5, -12.5).is_none());
        assert_eq!(ElevationModel::read(&tile(|_, _| 0), "elevation.hgt").err().unwrap().code, "invalid_terrain");
    }
}
