//! Wavefront OBJ models as scenes, read with `tobj`.
//!
//! Faces keep their vertex counts (no triangulation): the pipeline clips and scan
//! converts polygons of any size, and a quad drawn as one polygon has no interior edge.
//! A face takes the diffuse colour (`Kd`) of its material, scaled to 0–255; a face with
//! no material, or whose material library cannot be read, takes [`DEFAULT_COLOUR`].

use crate::shapes::Face;
use glam::DVec3;
use std::cell::RefCell;
use std::io::BufRead;
use std::path::{Path, PathBuf};

/// The colour of a face without a material.
pub const DEFAULT_COLOUR: proto::Colour = [200, 200, 200];

/// The radius the model's bounding sphere is scaled to by [`fit`]: inside the
/// visible square (half-side 12.5 at the origin) and between hither and yon (the
/// origin is at z_e = 20, yon at 30).
pub const FIT_RADIUS: f64 = 8.0;

/// A loaded model: its faces, and the warnings met on the way (a material library that
/// could not be read, a material that is not in any library).
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    pub faces: Vec<Face>,
    pub warnings: Vec<String>,
}

/// Reads an OBJ model. `dir` is where its `mtllib` files are looked for (the OBJ file's
/// folder, or the current one for standard input); `name` names it in messages.
pub fn load<R: BufRead>(input: &mut R, dir: &Path, name: &str) -> anyhow::Result<Model> {
    let warnings = RefCell::new(Vec::new());
    let options = tobj::LoadOptions {
        triangulate: false,
        single_index: true,
        ..Default::default()
    };
    let (models, materials) = tobj::load_obj_buf(input, &options, |mtl: &Path| {
        let path: PathBuf = dir.join(mtl);
        match tobj::load_mtl(&path) {
            Ok(m) => Ok(m),
            Err(e) => {
                warnings.borrow_mut().push(format!(
                    "cannot read material library {} ({e}); using default colours",
                    path.display()
                ));
                Ok((Vec::new(), Default::default()))
            }
        }
    })
    .map_err(|e| anyhow::anyhow!("{name}: not a valid OBJ file: {e}"))?;
    let mut warnings = warnings.into_inner();
    let materials = materials.unwrap_or_default();
    let mut faces = Vec::new();
    for model in &models {
        let mesh = &model.mesh;
        let colour = match mesh.material_id.and_then(|id| materials.get(id)) {
            Some(m) => match m.diffuse {
                Some(kd) => kd.map(|c| (c * 255.0).round().clamp(0.0, 255.0) as u8),
                None => DEFAULT_COLOUR,
            },
            None => DEFAULT_COLOUR,
        };
        let position = |i: u32| {
            let i = i as usize * 3;
            DVec3::new(
                mesh.positions[i],
                mesh.positions[i + 1],
                mesh.positions[i + 2],
            )
        };
        // face_arities is empty when every face is a triangle.
        let arities: Vec<usize> = if mesh.face_arities.is_empty() {
            vec![3; mesh.indices.len() / 3]
        } else {
            mesh.face_arities.iter().map(|&a| a as usize).collect()
        };
        let mut start = 0;
        for arity in arities {
            let Some(indices) = mesh.indices.get(start..start + arity) else {
                anyhow::bail!(
                    "{name}: object `{}` has a face past its index list",
                    model.name
                );
            };
            faces.push(Face::new(
                colour,
                indices.iter().map(|&i| position(i)).collect(),
            ));
            start += arity;
        }
    }
    if faces.is_empty() {
        warnings.push(format!("{name} has no faces"));
    }
    Ok(Model { faces, warnings })
}

/// Moves and scales the faces so that the model's bounding box is centred on the
/// origin and its bounding sphere has radius [`FIT_RADIUS`]: the whole model is then in
/// view of the default camera.
pub fn fit(faces: &mut [Face]) {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for p in faces.iter().flat_map(|f| &f.points) {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    if lo.x > hi.x {
        // No vertices.
        return;
    }
    let centre = (lo + hi) * 0.5;
    let radius = faces
        .iter()
        .flat_map(|f| &f.points)
        .map(|p| (*p - centre).length())
        .fold(0.0, f64::max);
    let scale = if radius > 0.0 {
        FIT_RADIUS / radius
    } else {
        1.0
    };
    for p in faces.iter_mut().flat_map(|f| &mut f.points) {
        *p = (*p - centre) * scale;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Cursor;

    fn load_str(text: &str) -> Model {
        load(
            &mut Cursor::new(text),
            Path::new("/nonexistent"),
            "test.obj",
        )
        .unwrap()
    }

    #[test]
    fn quads_and_ngons_keep_their_vertices() {
        let m = load_str(
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 1.5 0\n\
             f 1 2 3 4\nf 1 2 3 5 4\nf 1 2 3\n",
        );
        let counts: Vec<usize> = m.faces.iter().map(|f| f.points.len()).collect();
        assert_eq!(counts, [4, 5, 3]);
        assert_eq!(m.faces[1].points[3], DVec3::new(0.5, 1.5, 0.0));
        assert!(m.faces.iter().all(|f| f.colour == DEFAULT_COLOUR));
        assert!(m.warnings.is_empty());
    }

    #[test]
    fn negative_indices_count_back_from_the_last_vertex() {
        let m = load_str("v 0 0 0\nv 2 0 0\nv 2 2 0\nf -3 -2 -1\nv 9 9 9\nf 1 -1 -2\n");
        assert_eq!(
            m.faces[0].points,
            [
                DVec3::ZERO,
                DVec3::new(2.0, 0.0, 0.0),
                DVec3::new(2.0, 2.0, 0.0)
            ]
        );
        assert_eq!(
            m.faces[1].points,
            [DVec3::ZERO, DVec3::splat(9.0), DVec3::new(2.0, 2.0, 0.0)]
        );
    }

    #[test]
    fn fit_centres_and_scales() {
        let mut faces = vec![Face::new(
            DEFAULT_COLOUR,
            vec![
                DVec3::new(10.0, 10.0, 10.0),
                DVec3::new(12.0, 10.0, 10.0),
                DVec3::new(12.0, 10.0, 12.0),
            ],
        )];
        fit(&mut faces);
        let r = FIT_RADIUS / 2f64.sqrt();
        assert!((faces[0].points[0] - DVec3::new(-r, 0.0, -r)).length() < 1e-12);
        assert!((faces[0].points[2] - DVec3::new(r, 0.0, r)).length() < 1e-12);
    }

    #[test]
    fn a_bad_index_is_an_error() {
        let err = load(
            &mut Cursor::new("v 0 0 0\nf 1 2 3\n"),
            Path::new("."),
            "bad.obj",
        )
        .unwrap_err();
        assert_eq!(
            err.to_string(),
            "bad.obj: not a valid OBJ file: face vertex index out of bounds"
        );
    }
}
