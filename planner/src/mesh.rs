//! Wavefront OBJ meshes of structures: `v`, `f` and `o` records (other records are skipped),
//! read with limits, each object a mesh of its own in model metres.
//!
//! The model's axes are x east, y north and z up (`up: "y"`: x east, y up, z south, as many
//! modelling tools write). Faces are fanned into triangles; their winding is kept, so a face
//! wound counter-clockwise seen from outside (the format's convention) has its normal outside.
//!
//! ```
//! use coverplan_planner::mesh::{read_obj, Up};
//! let objects = read_obj("o shed\nv 0 0 0\nv 4 0 0\nv 4 3 0\nv 0 3 0\nf 1 2 3 4\n", Up::Z).unwrap();
//! assert_eq!((objects[0].name.as_str(), objects[0].triangles.len()), ("shed", 2));
//! ```

/// Most triangles a mission's meshes may hold, and most bytes of one OBJ text.
pub const MAX_TRIANGLES: usize = 200_000;
pub const MAX_OBJ_BYTES: usize = 8 << 20;

/// Which model axis points up.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Up {
    Z,
    Y,
}

/// One object of a model: its triangles' corners, in model metres (east, north, up).
#[derive(Debug, Clone, PartialEq)]
pub struct MeshObject {
    pub name: String,
    pub triangles: Vec<[[f64; 3]; 3]>,
}

/// The objects of an OBJ text; faces before any `o` record belong to an object named `mesh`.
/// Errors name the line.
pub fn read_obj(text: &str, up: Up) -> Result<Vec<MeshObject>, String> {
    if text.len() > MAX_OBJ_BYTES {
        return Err(format!("the model has {} bytes; the limit is {MAX_OBJ_BYTES}", text.len()));
    }
    let mut vertices: Vec<[f64; 3]> = Vec::new();
    let mut objects: Vec<MeshObject> = Vec::new();
    let mut triangles = 0usize;
    for (n, line) in text.lines().enumerate() {
        let at = n + 1;
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let xyz: Vec<f64> = words.take(3).map(str::parse::<f64>).collect::<Result<_, _>>().map_err(|e| format!("line {at}: {e}"))?;
                let [x, y, z] = <[f64; 3]>::try_from(xyz).map_err(|_| format!("line {at}: a vertex needs x, y and z"))?;
                if ![x, y, z].iter().all(|c| c.is_finite() && c.abs() < 1e5) {
                    return Err(format!("line {at}: coordinates must be finite and under 100 km"));
                }
                vertices.push(match up {
                    Up::Z => [x, y, z],
                    Up::Y => [x, -z, y],
                });
            }
            Some("o") => objects.push(MeshObject { name: words.collect::<Vec<_>>().join(" "), triangles: Vec::new() }),
            Some("f") => {
                let corners: Vec<[f64; 3]> = words
                    .map(|w| {
                        // `v`, `v/vt`, `v//vn` or `v/vt/vn`; negative indices count back
                        let i: i64 = w.split('/').next().unwrap_or("").parse().map_err(|_| format!("line {at}: `{w}` is not a vertex index"))?;
                        let index = if i < 0 { vertices.len() as i64 + i } else { i - 1 };
                        usize::try_from(index).ok().and_then(|k| vertices.get(k)).copied().ok_or_else(|| format!("line {at}: no vertex {i}"))
                    })
                    .collect::<Result<_, _>>()?;
                if corners.len() < 3 {
                    return Err(format!("line {at}: a face needs three vertices"));
                }
                if objects.is_empty() {
                    objects.push(MeshObject { name: "mesh".into(), triangles: Vec::new() });
                }
                let object = objects.last_mut().expect("an object");
                for k in 1..corners.len() - 1 {
                    object.triangles.push([corners[0], corners[k], corners[k + 1]]);
                }
                triangles += corners.len() - 2;
                if triangles > MAX_TRIANGLES {
                    return Err(format!("the model has more than {MAX_TRIANGLES} triangles"));
                }
            }
            _ => {}
        }
    }
    objects.retain(|o| !o.triangles.is_empty());
    if objects.is_empty() {
        return Err("the model has no face".into());
    }
    Ok(objects)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn objects_faces_and_axes() {
        let text = "# a box's floor and a tower\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1/1 2/2 3/3 4/4\no tower\nv 0 0 5\nf 1 2 -1\n";
        let objects = read_obj(text, Up::Z).unwrap();
        assert_eq!(objects.iter().map(|o| (o.name.as_str(), o.triangles.len())).collect::<Vec<_>>(), vec![("mesh", 2), ("tower", 1)]);
        assert_eq!(objects[1].triangles[0][2], [0.0, 0.0, 5.0]);
        let y_up = read_obj("v 1 2 3\nv 0 0 0\nv 1 0 0\nf 1 2 3\n", Up::Y).unwrap();
        assert_eq!(y_up[0].triangles[0][0], [1.0, -3.0, 2.0]);
    }

    #[test]
    fn bad_models_name_their_line() {
        assert!(read_obj("v 0 0\n", Up::Z).unwrap_err().contains("line 1"));
        assert!(read_obj("v 0 0 0\nf 1 2 3\n", Up::Z).unwrap_err().contains("no vertex 2"));
        assert!(read_obj("v 0 0 nan\n", Up::Z).unwrap_err().contains("line 1"));
        assert!(read_obj("v 0 0 0\n", Up::Z).unwrap_err().contains("no face"));
    }
}
