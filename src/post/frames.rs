//! Snapshots of a dynamic run for ParaView (docs/method.md §10.4): `frames.pvd`, the time
//! series that opens them, and per frame the nodes with their displacement and velocity as a
//! VTP point set (warp by `displacement` to see the deformed bodies).
//!
//! - One body: `frames/frame_<step>.vtp`, listed by `frames.pvd`.
//! - Several bodies: `frames/frame_<step>_<k>.vtp` for body `k` (`[[body]]` order) and
//!   `frames/frame_<step>.vtm`, a multiblock naming each body's file (the static run's
//!   `solution.vtm` convention), listed by `frames.pvd`: ParaView opens the series as one
//!   multiblock per time, so one "Warp By Vector" moves every body.

use super::paraview::{collection, multiblock};
use super::vtk::{Array, poly_data};
use super::{OutputError, create_dir, write_text};
use crate::dynamics::{BodyFrame, Frame};
use crate::geometry::Point;
use std::path::{Path, PathBuf};

/// Writes the frames of `bodies` (each body's name and node positions, in the frames' body
/// order) under `dir/frames/` and `dir/frames.pvd`; returns the files (the index last).
/// Nothing is written without frames.
///
/// # Errors
/// [`OutputError::Io`] when a file cannot be written.
pub fn write_frames(
    dir: &Path,
    bodies: &[(&str, &[Point])],
    frames: &[Frame],
) -> Result<Vec<PathBuf>, OutputError> {
    if frames.is_empty() {
        return Ok(Vec::new());
    }
    let folder = dir.join("frames");
    create_dir(&folder)?;
    // Each body's vertices (one per node), the same in every frame.
    let verts: Vec<Vec<Vec<usize>>> =
        bodies.iter().map(|(_, points)| (0..points.len()).map(|i| vec![i]).collect()).collect();
    let mut files = Vec::new();
    let mut entries = Vec::new();
    for f in frames {
        let stem = format!("frame_{:06}", f.step);
        let name = if let [(_, points)] = bodies {
            let name = format!("{stem}.vtp");
            let set = (*points, &verts[0][..]);
            files.push(write_body(&folder.join(&name), set, &f.bodies[0])?);
            name
        } else {
            let mut sets = Vec::with_capacity(bodies.len());
            for (k, ((body, points), fields)) in bodies.iter().zip(&f.bodies).enumerate() {
                let name = format!("{stem}_{k}.vtp");
                let set = (*points, &verts[k][..]);
                files.push(write_body(&folder.join(&name), set, fields)?);
                sets.push((body.to_string(), name));
            }
            let name = format!("{stem}.vtm");
            let path = folder.join(&name);
            write_text(&path, &multiblock(&[("bodies", sets)]))?;
            files.push(path);
            name
        };
        entries.push((f.time, format!("frames/{name}")));
    }
    let index = dir.join("frames.pvd");
    let listed: Vec<(f64, &str)> = entries.iter().map(|(t, n)| (*t, n.as_str())).collect();
    write_text(&index, &collection(&listed))?;
    files.push(index);
    Ok(files)
}

/// Writes one body's point set (its nodes and their vertices) with its `fields` to `path`;
/// returns the path.
fn write_body(
    path: &Path,
    (points, verts): (&[Point], &[Vec<usize>]),
    fields: &BodyFrame,
) -> Result<PathBuf, OutputError> {
    let point_data = [
        Array::Vector("displacement".into(), fields.displacement.clone()),
        Array::Vector("velocity".into(), fields.velocity.clone()),
    ];
    write_text(path, &poly_data(points, verts, &[], &point_data, &[], &[]))?;
    Ok(path.to_path_buf())
}
