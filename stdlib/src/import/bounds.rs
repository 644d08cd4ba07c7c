//! The grid a house is imported onto: bounds, side length, and the memory it will need, checked
//! before anything is allocated.
//!
//! A house may be small in cells yet large in bytes (a fine resolution, a stray vertex hundreds
//! of metres out), so the limit is expressed in memory: the import refuses up front, saying how
//! much it would need and how to raise the limit, instead of being killed by the system halfway.

use super::house::House;
use super::procthor::ImportOptions;
use crate::map::error::{ErrCtx, MapError};
use crate::map::format::MAX_GRID_SIZE;

/// Peak bytes per grid cell of an import, measured (`/usr/bin/time -f %M` on `m2rc map import`
/// of the largest fixture at fine resolutions, minus the process baseline), rounded up. The
/// memory check multiplies the cell count by it.
pub const IMPORT_BYTES_PER_CELL: u64 = 40;

/// Default memory limit of an import: 4 GB.
pub const DEFAULT_MAX_IMPORT_MEMORY: u64 = 4_000_000_000;

fn r6(x: f64) -> f64 {
    (x * 1_000_000.0).round() / 1_000_000.0
}

/// Where the grid sits: world origin of cell (0, 0), unpadded height and width, and side N.
pub(super) struct GridPlan {
    pub x_min: f64,
    pub x_max: f64,
    pub z_min: f64,
    pub z_max: f64,
    pub h: u64,
    pub w: u64,
    pub n: usize,
}

/// Human figure for a byte count (`1.3 GB`, `640 MB`).
pub fn format_bytes(b: f64) -> String {
    if b >= 1e9 {
        format!("{:.1} GB", b / 1e9)
    } else {
        format!("{:.0} MB", (b / 1e6).max(1.0))
    }
}

pub(super) fn plan_grid(
    house: &House,
    opts: &ImportOptions,
    ctx: &ErrCtx,
) -> Result<GridPlan, MapError> {
    let res = opts.resolution;
    let (mut x0, mut x1, mut z0, mut z1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for r in &house.rooms {
        for p in &r.polygon {
            x0 = x0.min(p[0]);
            x1 = x1.max(p[0]);
            z0 = z0.min(p[1]);
            z1 = z1.max(p[1]);
        }
    }
    let (x_min, x_max) = (r6(x0 - opts.padding_m), r6(x1 + opts.padding_m));
    let (z_min, z_max) = (r6(z0 - opts.padding_m), r6(z1 + opts.padding_m));
    // Side lengths in f64 first: a coordinate far out must not overflow the integer cast.
    let wf = ((x_max - x_min) / res - 1e-9).ceil() + 1.0;
    let hf = ((z_max - z_min) / res - 1e-9).ceil() + 1.0;
    let nf = wf.max(hf);
    if !nf.is_finite() || nf > MAX_GRID_SIZE as f64 {
        return Err(ctx.err(
            "rooms",
            format!(
                "the floor polygons span {:.1} x {:.1} m: {nf:.0} cells a side at {res} m per \
                 cell, more than the {MAX_GRID_SIZE} a map may have; use a coarser --resolution \
                 or check the polygons for a stray vertex",
                x1 - x0,
                z1 - z0
            ),
        ));
    }
    let need = nf * nf * IMPORT_BYTES_PER_CELL as f64;
    if need > opts.max_memory_bytes as f64 {
        return Err(ctx.err(
            "rooms",
            format!(
                "importing needs about {} ({nf:.0} x {nf:.0} cells at {res} m per cell, {:.1} x \
                 {:.1} m of floor plus padding), more than the {} memory limit; raise it with \
                 --max-memory (e.g. --max-memory {}) or use a coarser --resolution",
                format_bytes(need),
                x1 - x0,
                z1 - z0,
                format_bytes(opts.max_memory_bytes as f64),
                format_bytes((need * 1.25).max(1e9)).replace(' ', "")
            ),
        ));
    }
    Ok(GridPlan {
        x_min,
        x_max,
        z_min,
        z_max,
        h: hf as u64,
        w: wf as u64,
        n: nf as usize,
    })
}

/// Parses a memory size such as `8G`, `512M`, `2.5GB`, `1000000` (bytes).
pub fn parse_memory(s: &str) -> Result<u64, String> {
    let t = s.trim();
    let lower = t.to_ascii_lowercase();
    let lower = lower.strip_suffix('b').unwrap_or(&lower);
    let (num, mult) = match lower.chars().last() {
        Some('k') => (&lower[..lower.len() - 1], 1e3),
        Some('m') => (&lower[..lower.len() - 1], 1e6),
        Some('g') => (&lower[..lower.len() - 1], 1e9),
        Some('t') => (&lower[..lower.len() - 1], 1e12),
        _ => (lower, 1.0),
    };
    match num.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 && v * mult < 1.8e19 => Ok((v * mult) as u64),
        _ => Err(format!(
            "{s:?} is not a memory size; write it like 8G, 512M or 2.5GB"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_sizes_parse() {
        assert_eq!(parse_memory("8G"), Ok(8_000_000_000));
        assert_eq!(parse_memory("512mb"), Ok(512_000_000));
        assert_eq!(parse_memory("2.5GB"), Ok(2_500_000_000));
        assert_eq!(parse_memory("1000"), Ok(1000));
        assert!(parse_memory("lots").is_err());
        assert!(parse_memory("-1G").is_err());
        assert!(parse_memory("").is_err());
    }
}
