//! A little-endian CDR (XCDR1) encoder for the few ROS 2 messages the MCAP export writes: what
//! `rmw` puts on the wire and `ros2 bag` records, so players and Foxglove decode it from the
//! schema alone. Primitives are aligned to their size from the start of the payload, after the
//! 4-byte encapsulation header.

pub struct Cdr {
    buf: Vec<u8>,
}

impl Cdr {
    pub fn new() -> Self {
        // CDR_LE encapsulation, no options.
        Cdr {
            buf: vec![0x00, 0x01, 0x00, 0x00],
        }
    }

    pub fn finish(self) -> Vec<u8> {
        self.buf
    }

    fn align(&mut self, n: usize) {
        while !(self.buf.len() - 4).is_multiple_of(n) {
            self.buf.push(0);
        }
    }

    #[cfg(test)]
    pub fn u8(&mut self, v: u8) {
        self.buf.push(v);
    }

    pub fn bool(&mut self, v: bool) {
        self.buf.push(v as u8);
    }

    pub fn i32(&mut self, v: i32) {
        self.align(4);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    pub fn u32(&mut self, v: u32) {
        self.align(4);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    pub fn f32(&mut self, v: f32) {
        self.align(4);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    pub fn f64(&mut self, v: f64) {
        self.align(8);
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    pub fn string(&mut self, s: &str) {
        self.seq_len(s.len() + 1);
        self.buf.extend_from_slice(s.as_bytes());
        self.buf.push(0);
    }

    /// A sequence length.
    pub fn seq_len(&mut self, n: usize) {
        self.u32(n as u32);
    }

    pub fn bytes(&mut self, b: &[u8]) {
        self.seq_len(b.len());
        self.buf.extend_from_slice(b);
    }

    /// `std_msgs/Header` with a zero stamp.
    pub fn header(&mut self, frame_id: &str) {
        self.i32(0);
        self.u32(0);
        self.string(frame_id);
    }

    /// `geometry_msgs/Pose` at `(x, y, z)` turned by `yaw` about z.
    pub fn pose(&mut self, x: f64, y: f64, z: f64, yaw: f64) {
        self.f64(x);
        self.f64(y);
        self.f64(z);
        let (s, c) = (yaw / 2.0).sin_cos();
        for q in [0.0, 0.0, s, c] {
            self.f64(q);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primitives_align_from_the_payload_start() {
        let mut c = Cdr::new();
        c.u8(7);
        c.f64(1.0);
        let b = c.finish();
        // header (4) + u8 (1) + 7 padding + f64 (8)
        assert_eq!(b.len(), 4 + 16);
        assert_eq!(b[5..12], [0; 7]);
        let mut c = Cdr::new();
        c.string("map");
        assert_eq!(c.finish()[4..], [4, 0, 0, 0, b'm', b'a', b'p', 0]);
    }
}
