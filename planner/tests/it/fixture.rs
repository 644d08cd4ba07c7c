//! Pieces of the hand-made maps the tests draw: a rectangle of cells, an object on its footprint.

use m2rc_stdlib::grid::Cell;
use m2rc_stdlib::map::Object;

/// The cells of rows `rows` by columns `cols`, row by row.
pub fn cells(rows: std::ops::Range<u32>, cols: std::ops::Range<u32>) -> Vec<Cell> {
    rows.flat_map(|r| cols.clone().map(move |c| Cell::new(r, c)))
        .collect()
}

/// Object `id` of `category` in room `room`, centred on its footprint.
pub fn object(id: u32, category: &str, footprint: Vec<Cell>, room: u32) -> Object {
    let k = footprint.len() as f64;
    let center = [
        footprint.iter().map(|c| c.row as f64).sum::<f64>() / k,
        footprint.iter().map(|c| c.col as f64).sum::<f64>() / k,
    ];
    Object {
        id,
        category: category.into(),
        name: format!("{category} {id}"),
        footprint,
        center,
        elevation_m: None,
        height_m: None,
        room: Some(room),
        parent: None,
        attributes: vec![],
    }
}
