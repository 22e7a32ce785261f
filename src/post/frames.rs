//! Snapshots of a dynamic run for ParaView (docs/method.md §10.4): one VTP point set per
//! frame (`frames/frame_<step>.vtp`: the nodes with their displacement and velocity; warp by
//! `displacement` to see the deformed body) and `frames.pvd`, the time series that opens them.

use super::vtk::{Array, poly_data};
use super::{OutputError, create_dir, paraview::collection, write_text};
use crate::dynamics::Frame;
use crate::geometry::Point;
use std::path::{Path, PathBuf};

/// Writes the frames under `dir/frames/` and `dir/frames.pvd`; returns the files (the
/// index last). Nothing is written without frames.
///
/// # Errors
/// [`OutputError::Io`] when a file cannot be written.
pub fn write_frames(
    dir: &Path,
    points: &[Point],
    frames: &[Frame],
) -> Result<Vec<PathBuf>, OutputError> {
    if frames.is_empty() {
        return Ok(Vec::new());
    }
    let folder = dir.join("frames");
    create_dir(&folder)?;
    let verts: Vec<Vec<usize>> = (0..points.len()).map(|i| vec![i]).collect();
    let mut files = Vec::new();
    let mut entries = Vec::new();
    for f in frames {
        let name = format!("frames/frame_{:06}.vtp", f.step);
        let point_data = [
            Array::Vector("displacement".into(), f.displacement.clone()),
            Array::Vector("velocity".into(), f.velocity.clone()),
        ];
        let path = dir.join(&name);
        write_text(&path, &poly_data(points, &verts, &[], &point_data, &[], &[]))?;
        files.push(path);
        entries.push((f.time, name));
    }
    let index = dir.join("frames.pvd");
    let listed: Vec<(f64, &str)> = entries.iter().map(|(t, n)| (*t, n.as_str())).collect();
    write_text(&index, &collection(&listed))?;
    files.push(index);
    Ok(files)
}
