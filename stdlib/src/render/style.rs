//! The colours of the drawing, in one place so the map, the legend and the overlays agree.
//!
//! Room tints are pale so that furniture, doorways and routes drawn on top stay the loudest thing
//! in the picture; doorways are green ("you can pass here") and windows blue, as on architects'
//! plans; routes take saturated colours that none of the base layers use.

/// An sRGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Rgb(pub u8, pub u8, pub u8);

impl Rgb {
    /// `#rrggbb`, as written into the SVG.
    pub fn hex(self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.0, self.1, self.2)
    }
}

/// Fill of a room by its category; unknown categories get a stable pastel derived from the name.
pub fn room_fill(category: &str) -> Rgb {
    match category {
        "bathroom" => Rgb(0xcd, 0xe6, 0xf5),
        "bedroom" => Rgb(0xde, 0xd6, 0xf2),
        "kitchen" => Rgb(0xfb, 0xe5, 0xb4),
        "living_room" => Rgb(0xf7, 0xd6, 0xcb),
        other => pastel(other),
    }
}

/// A pale colour picked by a deterministic hash of `name` (FNV-1a), for categories without a
/// fixed colour.
fn pastel(name: &str) -> Rgb {
    let mut h: u32 = 0x811c_9dc5;
    for b in name.bytes() {
        h ^= b as u32;
        h = h.wrapping_mul(0x0100_0193);
    }
    let ch = |shift: u32| 0xc8 + ((h >> shift) & 0x2f) as u8;
    Rgb(ch(0), ch(8), ch(16))
}

pub const BACKGROUND: &str = "#ffffff";
/// Cells outside every room that are not free: the exterior of the house and the padding.
pub const OUTSIDE: &str = "#ececec";
/// Free cells outside every room.
pub const FREE_NO_ROOM: &str = "#fafafa";
/// Obstacle cells inside a room (furniture and the robot-radius margin around walls and
/// furniture), drawn as a translucent shade so the room tint still shows through.
pub const OBSTACLE: &str = "#3c3c3c";
pub const OBSTACLE_OPACITY: f64 = 0.2;
pub const UNKNOWN: &str = "#b0b0b0";
pub const WALL: &str = "#2b2b2b";
pub const DOORWAY: &str = "#1fa64a";
pub const WINDOW: &str = "#2f80ed";
/// Open boundaries between open-plan rooms: the doorway green, dashed (passable, no wall).
pub const OPEN_BOUNDARY: &str = "#1fa64a";
pub const FURNITURE_FILL: &str = "#f6f3ec";
pub const FURNITURE_STROKE: &str = "#5f5a52";
pub const SMALL_FILL: &str = "#ffffff";
pub const SMALL_STROKE: &str = "#9a958c";
pub const TEXT: &str = "#1d1d1d";
pub const TEXT_MUTED: &str = "#55524c";
pub const START: &str = "#e0115f";

/// Route colours, used in order for routes without an explicit colour and for the stages of a
/// staged route.
pub const ROUTE_PALETTE: [Rgb; 8] = [
    Rgb(0xd6, 0x28, 0x28),
    Rgb(0x7b, 0x2c, 0xbf),
    Rgb(0xf7, 0x7f, 0x00),
    Rgb(0x00, 0x81, 0xa7),
    Rgb(0xc2, 0x18, 0x5b),
    Rgb(0x3a, 0x5a, 0x40),
    Rgb(0x6d, 0x59, 0x7a),
    Rgb(0xb0, 0x89, 0x00),
];

/// The object categories drawn as building structure rather than furniture.
pub fn structure_kind(category: &str) -> Option<Structure> {
    match category {
        "wall" => Some(Structure::Wall),
        "doorway" | "doorframe" | "door" => Some(Structure::Doorway),
        "window" => Some(Structure::Window),
        _ => None,
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Structure {
    Wall,
    Window,
    Doorway,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pastel_is_stable_and_pale() {
        let a = room_fill("garage");
        assert_eq!(a, room_fill("garage"));
        assert!(a.0 >= 0xc8 && a.1 >= 0xc8 && a.2 >= 0xc8);
        assert_eq!(Rgb(1, 2, 255).hex(), "#0102ff");
    }
}
