use std::io::Write;

use meshmorph::io::gltf::glb::*;

/// Pieces made now and later: written in order, whether the later ones
/// come in one batch or many.
fn pieces(later: usize) -> (Pieces<'static>, Vec<u8>) {
    let mut pieces = Pieces::default();
    let mut expected = Vec::new();
    for k in 0..later {
        let made = vec![k as u8; k % 3];
        expected.extend_from_slice(&made);
        pieces.push(made);
        let len = 1000 + k;
        expected.extend((0..len).map(|i| (i * 7 + k) as u8));
        pieces.push_later(len, move |bytes| {
            bytes.extend((0..len).map(|i| (i * 7 + k) as u8));
        });
    }
    (pieces, expected)
}

#[test]
fn later_pieces_are_written_in_their_place() {
    for later in [0, 1, 5, 40] {
        let (pieces, expected) = pieces(later);
        assert_eq!(pieces.len(), expected.len());
        assert_eq!(pieces.concat(), expected, "{later} later pieces");
    }
}

/// A writer that fails after `room` bytes.
struct Full {
    room: usize,
}

impl Write for Full {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if self.room == 0 {
            return Err(std::io::Error::other("no room left"));
        }
        let n = buf.len().min(self.room);
        self.room -= n;
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

#[test]
fn a_failing_writer_stops_the_pieces_with_its_error() {
    let (pieces, expected) = pieces(40);
    for room in [0, 10, expected.len() / 2, expected.len() - 1] {
        let error = pieces.write_to(&mut Full { room }).unwrap_err();
        assert_eq!(error.to_string(), "no room left");
    }
    assert!(pieces
        .write_to(&mut Full {
            room: expected.len()
        })
        .is_ok());
}

#[test]
fn sparse_and_dense_deltas_lay_out_what_moves() {
    // 300 vertices (2-byte indices), every 10th moving: sparse; with
    // `sparse` off, or every vertex moving: dense.
    let deltas: Vec<[f32; 3]> = (0..300)
        .map(|v| {
            if v % 10 == 3 {
                [v as f32, -1.0, 0.5]
            } else {
                [0.0; 3]
            }
        })
        .collect();
    let summary = DeltaSummary::of(deltas.len(), |v| deltas[v]);
    assert!(summary.finite);
    assert_eq!(summary.moved, 30);
    let sparse = summary.layout(true);
    assert_eq!(sparse.index_type, Some(5123));
    let mut bytes = Vec::new();
    sparse.fill(|v| deltas[v], &mut bytes);
    assert_eq!(bytes.len(), sparse.len);
    let index = |i: usize| u16::from_le_bytes([bytes[2 * i], bytes[2 * i + 1]]) as usize;
    let value = |i: usize, c: usize| {
        let at = sparse.values_at + 12 * i + 4 * c;
        f32::from_le_bytes(bytes[at..at + 4].try_into().unwrap())
    };
    for i in 0..30 {
        assert_eq!(index(i), 10 * i + 3);
        assert_eq!([value(i, 0), value(i, 1), value(i, 2)], deltas[10 * i + 3]);
    }
    let dense = summary.layout(false);
    assert_eq!((dense.index_type, dense.len), (None, 12 * 300));
    let mut bytes = Vec::new();
    dense.fill(|v| deltas[v], &mut bytes);
    assert_eq!(bytes, float_bytes(deltas.as_flattened()));
    let still = DeltaSummary::of(10, |_| [0.0; 3]);
    assert_eq!(still.layout(true).len, 0);
    assert!(!DeltaSummary::of(3, |v| [0.0, f32::NAN * v as f32, 0.0]).finite);
}
