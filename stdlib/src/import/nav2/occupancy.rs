//! The Nav2 image as an occupancy layer: pixels classified exactly as `map_server` does, the
//! image flipped so that its top row is the grid's last (the OccupancyGrid rule), padded to the
//! square Map2Route grid with unknown cells above and to the right, then eroded by the robot
//! radius like a house.

use super::params::{MapYaml, Mode};
use crate::field::{NO_SOURCE, squared_distances};
use crate::grid::Grid;
use crate::import::bounds::{IMPORT_BYTES_PER_CELL, format_bytes};
use crate::map::error::{ErrCtx, MapError};
use crate::map::format::MAX_GRID_SIZE;
use crate::map::{FREE, OBSTACLE, UNKNOWN};

/// The occupancy layer and the image's size.
pub struct Occupancy {
    pub grid: Grid<u8>,
    /// Image width and height in pixels (before padding).
    pub width: usize,
    pub height: usize,
}

/// What `map_server` makes of one pixel: 0 free, 100 occupied, -1 unknown, or a value in
/// between (`scale` and `raw` modes). `grey` is the mean of the colour channels in [0, 1];
/// `opaque` whether the alpha channel is full.
pub fn classify(y: &MapYaml, grey: f64, opaque: bool) -> i8 {
    let occ = if y.negate { grey } else { 1.0 - grey };
    match y.mode {
        Mode::Trinary => {
            if y.occupied_thresh < occ {
                100
            } else if occ < y.free_thresh {
                0
            } else {
                -1
            }
        }
        Mode::Scale => {
            if !opaque {
                -1
            } else if y.occupied_thresh < occ {
                100
            } else if occ < y.free_thresh {
                0
            } else {
                ((occ - y.free_thresh) / (y.occupied_thresh - y.free_thresh) * 100.0).round() as i8
            }
        }
        Mode::Raw => {
            let v = (grey * 255.0).round();
            if (0.0..=100.0).contains(&v) {
                v as i8
            } else {
                -1
            }
        }
    }
}

/// Reads and classifies the image named by the YAML. A cell is traversable only where
/// `map_server` says free (0); unknown (-1) stays unknown; anything else is an obstacle.
pub fn read_occupancy(
    y: &MapYaml,
    robot_radius_m: f64,
    max_memory: u64,
) -> Result<Occupancy, MapError> {
    let file = y.image.display().to_string();
    let ctx = ErrCtx::new(&file);
    let mut reader = image::ImageReader::open(&y.image)
        .and_then(|r| r.with_guessed_format())
        .map_err(|e| ctx.err("", format!("cannot read the map image: {e}")))?;
    let (w, h) = {
        let probe = image::ImageReader::open(&y.image)
            .and_then(|r| r.with_guessed_format())
            .map_err(|e| ctx.err("", format!("cannot read the map image: {e}")))?;
        probe
            .into_dimensions()
            .map_err(|e| ctx.err("", format!("not a PGM or PNG image: {e}")))?
    };
    let (w, h) = (w as usize, h as usize);
    let n = w.max(h);
    if n == 0 {
        return Err(ctx.err("", "the image is empty"));
    }
    if n as u64 > MAX_GRID_SIZE {
        return Err(ctx.err(
            "",
            format!(
                "the image is {w}x{h} pixels; the square grid would be {n} cells a side, more \
                 than the {MAX_GRID_SIZE} a map may have (downsample it, e.g. with a coarser resolution)"
            ),
        ));
    }
    let need = (n as u64) * (n as u64) * IMPORT_BYTES_PER_CELL + (w as u64) * (h as u64) * 4;
    if need > max_memory {
        return Err(ctx.err(
            "",
            format!(
                "importing this {w}x{h} image needs about {} of memory, more than the limit of {}; \
                 raise it with --max-memory",
                format_bytes(need as f64),
                format_bytes(max_memory as f64)
            ),
        ));
    }
    let mut limits = image::Limits::default();
    limits.max_alloc = Some(max_memory);
    reader.limits(limits);
    let img = reader
        .decode()
        .map_err(|e| ctx.err("", format!("cannot decode the map image: {e}")))?;
    let mut grid = Grid::new(n, UNKNOWN);
    let mut put = |x: usize, row_in_image: usize, v: i8| {
        let row = h - 1 - row_in_image;
        let o = match v {
            0 => FREE,
            -1 => UNKNOWN,
            _ => OBSTACLE,
        };
        grid.data_mut()[row * n + x] = o;
    };
    match &img {
        image::DynamicImage::ImageLuma8(g) => {
            for (x, yy, p) in g.enumerate_pixels() {
                put(
                    x as usize,
                    yy as usize,
                    classify(y, p.0[0] as f64 / 255.0, true),
                );
            }
        }
        other => {
            let rgba = other.to_rgba8();
            for (x, yy, p) in rgba.enumerate_pixels() {
                let [r, g, b, a] = p.0;
                let grey = (r as f64 + g as f64 + b as f64) / 3.0 / 255.0;
                put(x as usize, yy as usize, classify(y, grey, a == 255));
            }
        }
    }
    drop(img);
    if robot_radius_m > 0.0 {
        erode(&mut grid, robot_radius_m / y.resolution);
    }
    Ok(Occupancy {
        grid,
        width: w,
        height: h,
    })
}

/// Free cells closer than `r_cells` to any cell that is not free become obstacles (the exact
/// distance transform, as for houses).
pub fn erode(grid: &mut Grid<u8>, r_cells: f64) {
    let n = grid.n();
    let blocked: Vec<bool> = grid.data().iter().map(|&o| o != FREE).collect();
    let d2 = squared_distances(&blocked, n);
    let limit = r_cells * r_cells - 1e-9;
    for (o, &d) in grid.data_mut().iter_mut().zip(&d2) {
        if *o == FREE && d != NO_SOURCE && (d as f64) < limit {
            *o = OBSTACLE;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn yaml(mode: Mode, negate: bool) -> MapYaml {
        MapYaml {
            image: PathBuf::new(),
            resolution: 0.05,
            origin: [0.0; 3],
            negate,
            occupied_thresh: 0.65,
            free_thresh: 0.196,
            mode,
        }
    }

    #[test]
    fn pixels_are_classified_as_map_server_does() {
        let t = yaml(Mode::Trinary, false);
        assert_eq!(classify(&t, 1.0, true), 0); // white: free
        assert_eq!(classify(&t, 0.0, true), 100); // black: occupied
        assert_eq!(classify(&t, 205.0 / 255.0, true), -1); // map_saver's grey: unknown
        assert_eq!(classify(&yaml(Mode::Trinary, true), 1.0, true), 100);
        let s = yaml(Mode::Scale, false);
        assert_eq!(classify(&s, 0.5, false), -1);
        assert_eq!(classify(&s, 0.5, true), 67); // (0.5 - 0.196) / (0.65 - 0.196)
        let r = yaml(Mode::Raw, false);
        assert_eq!(classify(&r, 42.0 / 255.0, true), 42);
        assert_eq!(classify(&r, 1.0, true), -1);
    }

    #[test]
    fn erosion_keeps_cells_at_least_the_radius_away() {
        let mut g = Grid::new(9, FREE);
        g.set(crate::grid::Cell::new(4, 4), OBSTACLE);
        erode(&mut g, 2.0);
        assert_eq!(g.get(crate::grid::Cell::new(4, 5)), Some(&OBSTACLE));
        assert_eq!(g.get(crate::grid::Cell::new(5, 5)), Some(&OBSTACLE));
        assert_eq!(g.get(crate::grid::Cell::new(4, 6)), Some(&FREE));
    }
}
