//! Packing chart shapes instead of their bounding rectangles, as xatlas
//! does: a triangle-shaped or L-shaped chart leaves half its rectangle
//! empty, and another chart can use that space.
//!
//! Each chart at a given scale becomes, per texel row, the span of texels
//! its triangles touch (conservative: any overlap counts; a row's gaps
//! between two parts of a chart are filled, which keeps the test cheap and
//! loses little). Charts go largest first to the first free position in
//! reading order (top row first, then left), in whichever of its four
//! quarter turns ends higher up (then further left). A placed chart
//! marks its spans grown by the padding in every direction, and the atlas
//! border is marked as wide, so any two charts' texels stay at least
//! `padding` texels apart, as the rectangle packer guarantees.

/// Texel spans of a chart, per row from its top: `(first, last)` texel,
/// inclusive; `first > last` for an empty row.
struct Spans {
    rows: Vec<(i64, i64)>,
    width: i64,
    /// Rows by decreasing span length: the widest collide first, and the
    /// widest alone rejects most positions.
    order: Vec<usize>,
}

/// Where one chart went: the texel origin of its spans and how many
/// quarter turns it was given ([`place_point`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Spot {
    pub origin: [u32; 2],
    pub turns: u8,
}

/// A chart's corner `q` (chart units, within `[0, width] × [0, height]`)
/// at `scale`, turned by `turns` quarter turns (rotations: triangles keep
/// their orientation), in texels relative to its spot's origin.
pub(super) fn place_point(q: [f64; 2], size: [f64; 2], scale: f64, turns: u8) -> [f64; 2] {
    let [w, h] = size;
    let p = match turns % 4 {
        0 => q,
        1 => [h - q[1], q[0]],
        2 => [w - q[0], h - q[1]],
        _ => [q[1], w - q[0]],
    };
    [p[0] * scale, p[1] * scale]
}

/// The chart's spans; none, and a width no atlas holds, when it reaches
/// past `limit` texels (a sliver at a trial scale: its rows are not
/// allocated).
fn spans(coords: &[[f64; 2]], size: [f64; 2], scale: f64, turns: u8, limit: f64) -> Spans {
    let pts: Vec<[f64; 2]> = coords
        .iter()
        .map(|&q| place_point(q, size, scale, turns))
        .map(|p| [p[0].max(0.0), p[1].max(0.0)])
        .collect();
    let top = pts.iter().map(|p| p[1]).fold(0.0, f64::max);
    let right = pts.iter().map(|p| p[0]).fold(0.0, f64::max);
    if !(top <= limit && right <= limit) {
        return Spans {
            rows: Vec::new(),
            width: i64::MAX,
            order: Vec::new(),
        };
    }
    let n_rows = (top.ceil() as usize).max(1);
    let mut rows = vec![(i64::MAX, i64::MIN); n_rows];
    for t in pts.chunks_exact(3) {
        let y_lo = t.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
        let y_hi = t.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
        let r0 = (y_lo.floor() as usize).min(n_rows - 1);
        let r1 = ((y_hi.ceil() as usize).max(r0 + 1)).min(n_rows);
        for (r, row) in rows.iter_mut().enumerate().take(r1).skip(r0) {
            // The triangle's x extent within the strip [r, r + 1]: its
            // corners inside the strip and its edges' crossings of the
            // strip's two lines.
            let (lo, hi) = (r as f64, r as f64 + 1.0);
            let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if a[1] >= lo && a[1] <= hi {
                    x0 = x0.min(a[0]);
                    x1 = x1.max(a[0]);
                }
                for line in [lo, hi] {
                    if (a[1] - line) * (b[1] - line) < 0.0 {
                        let x = a[0] + (b[0] - a[0]) * (line - a[1]) / (b[1] - a[1]);
                        x0 = x0.min(x);
                        x1 = x1.max(x);
                    }
                }
            }
            if x0 > x1 {
                continue;
            }
            let first = x0.floor() as i64;
            let last = (x1.ceil() as i64 - 1).max(first);
            row.0 = row.0.min(first);
            row.1 = row.1.max(last);
        }
    }
    let width = rows.iter().map(|r| r.1 + 1).max().unwrap_or(1).max(1);
    let mut order: Vec<usize> = (0..rows.len())
        .filter(|&r| rows[r].0 <= rows[r].1)
        .collect();
    order.sort_by_key(|&r| (std::cmp::Reverse(rows[r].1 - rows[r].0), r));
    Spans { rows, width, order }
}

/// Occupied texels, one bit each, rows of 64-bit words.
struct Occupancy {
    size: i64,
    words: usize,
    bits: Vec<u64>,
    /// Longest run of free texels in every row: a row that cannot hold a
    /// chart's span is rejected without a scan.
    free_run: Vec<i64>,
}

impl Occupancy {
    fn new(size: u32) -> Self {
        let words = (size as usize).div_ceil(64);
        Occupancy {
            size: i64::from(size),
            words,
            bits: vec![0; words * size as usize],
            free_run: vec![i64::from(size); size as usize],
        }
    }

    fn update_free_run(&mut self, y: i64) {
        let row = &self.bits[y as usize * self.words..(y as usize + 1) * self.words];
        let (mut best, mut run) = (0i64, 0i64);
        for (w, &word) in row.iter().enumerate() {
            // Bits past the atlas's side count as occupied.
            let valid = (self.size - 64 * w as i64).min(64);
            let word = if valid < 64 {
                word | (!0u64 << valid)
            } else {
                word
            };
            match word {
                0 => run += 64,
                u64::MAX => {
                    best = best.max(run);
                    run = 0;
                }
                _ => {
                    for x in 0..64 {
                        if word >> x & 1 == 0 {
                            run += 1;
                        } else {
                            best = best.max(run);
                            run = 0;
                        }
                    }
                }
            }
        }
        self.free_run[y as usize] = best.max(run);
    }

    /// Marks texels `x0..=x1` of row `y` (clipped to the atlas).
    fn set(&mut self, y: i64, x0: i64, x1: i64) {
        if self.set_bits(y, x0, x1) {
            self.update_free_run(y);
        }
    }

    /// [`Occupancy::set`] without updating the row's free run; whether a
    /// bit was set.
    fn set_bits(&mut self, y: i64, x0: i64, x1: i64) -> bool {
        if y < 0 || y >= self.size {
            return false;
        }
        let (x0, x1) = (x0.max(0), x1.min(self.size - 1));
        if x0 > x1 {
            return false;
        }
        let row = &mut self.bits[y as usize * self.words..(y as usize + 1) * self.words];
        for x in x0..=x1 {
            row[x as usize / 64] |= 1 << (x % 64);
        }
        true
    }

    /// The last occupied texel among `x0..=x1` of row `y` (all of them
    /// inside the atlas).
    fn last_set(&self, y: i64, x0: i64, x1: i64) -> Option<i64> {
        let row = &self.bits[y as usize * self.words..(y as usize + 1) * self.words];
        let (w0, w1) = (x0 as usize / 64, x1 as usize / 64);
        for w in (w0..=w1).rev() {
            let mut word = row[w];
            if w == w1 {
                let keep = x1 as usize % 64;
                if keep < 63 {
                    word &= (1u64 << (keep + 1)) - 1;
                }
            }
            if w == w0 {
                word &= !0u64 << (x0 as usize % 64);
            }
            if word != 0 {
                return Some((w * 64 + 63 - word.leading_zeros() as usize) as i64);
            }
        }
        None
    }

    /// The first position, in reading order, where `s` meets no occupied
    /// texel, with its top row at most `y_max`.
    fn first_fit(&self, s: &Spans, y_max: i64) -> Option<[i64; 2]> {
        let h = s.rows.len() as i64;
        if h > self.size || s.width > self.size {
            return None;
        }
        // The row that last collided is tried first: neighbouring
        // positions mostly collide on the same row.
        let mut last_hit = s.order.first().copied().unwrap_or(0);
        'y: for y in 0..=(self.size - h).min(y_max) {
            for &r in &s.order {
                let (a, b) = s.rows[r];
                if self.free_run[y as usize + r] < b - a + 1 {
                    continue 'y;
                }
            }
            let mut x = 0;
            'x: while x + s.width <= self.size {
                for &r in std::iter::once(&last_hit).chain(&s.order) {
                    let (a, b) = s.rows[r];
                    if a > b {
                        continue;
                    }
                    if let Some(hit) = self.last_set(y + r as i64, x + a, x + b) {
                        last_hit = r;
                        // No position up to the one that clears this hit
                        // can fit.
                        x = hit - a + 1;
                        continue 'x;
                    }
                }
                return Some([x, y]);
            }
        }
        None
    }

    /// Marks `s` at `at`, grown by `pad` texels in every direction.
    fn mark(&mut self, s: &Spans, at: [i64; 2], pad: i64) {
        let h = s.rows.len() as i64;
        for y in -pad..h + pad {
            let (mut a, mut b) = (i64::MAX, i64::MIN);
            for r in (y - pad).max(0)..(y + pad + 1).min(h) {
                let (ra, rb) = s.rows[r as usize];
                if ra <= rb {
                    a = a.min(ra);
                    b = b.max(rb);
                }
            }
            if a <= b {
                self.set(at[1] + y, at[0] + a - pad, at[0] + b + pad);
            }
        }
    }
}

/// Places every chart (`(coords, width, height)`, corners three per
/// triangle within `[0, width] × [0, height]`) at `scale` in a `size`²
/// atlas, `pad` texels apart and from the border; `None` when one does not
/// fit.
pub(super) fn pack_shapes(
    charts: &[(&[[f64; 2]], f64, f64)],
    scale: f64,
    pad: u32,
    size: u32,
) -> Option<Vec<Spot>> {
    let mut occupancy = Occupancy::new(size);
    let pad = i64::from(pad);
    let n = i64::from(size);
    for y in 0..n {
        if y < pad || y >= n - pad {
            occupancy.set_bits(y, 0, n - 1);
        } else if pad > 0 {
            occupancy.set_bits(y, 0, pad - 1);
            occupancy.set_bits(y, n - pad, n - 1);
        }
        occupancy.update_free_run(y);
    }
    let shapes: Vec<[Spans; 4]> = charts
        .iter()
        .map(|&(c, w, h)| [0, 1, 2, 3].map(|turns| spans(c, [w, h], scale, turns, f64::from(size))))
        .collect();
    let texels = |s: &Spans| -> i64 { s.rows.iter().map(|&(a, b)| (b - a + 1).max(0)).sum() };
    let mut order: Vec<usize> = (0..charts.len()).collect();
    order.sort_by_key(|&i| {
        let most = shapes[i].iter().map(texels).max().unwrap_or(0);
        (std::cmp::Reverse(most), i)
    });
    let mut spots = vec![
        Spot {
            origin: [0, 0],
            turns: 0,
        };
        charts.len()
    ];
    for i in order {
        let mut best: Option<([i64; 2], usize)> = None;
        for (k, s) in shapes[i].iter().enumerate() {
            // Only a spot ending higher than the best so far can win.
            let y_max = best.map_or(i64::MAX, |(b, j)| {
                b[1] + shapes[i][j].rows.len() as i64 - s.rows.len() as i64
            });
            if let Some(at) = occupancy.first_fit(s, y_max) {
                let bottom = at[1] + s.rows.len() as i64;
                let better = match best {
                    None => true,
                    Some((b, j)) => {
                        let b_bottom = b[1] + shapes[i][j].rows.len() as i64;
                        (bottom, at[0]) < (b_bottom, b[0])
                    }
                };
                if better {
                    best = Some((at, k));
                }
            }
        }
        let (at, k) = best?;
        occupancy.mark(&shapes[i][k], at, pad);
        spots[i] = Spot {
            origin: [at[0] as u32, at[1] as u32],
            turns: k as u8,
        };
    }
    Some(spots)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A right triangle with legs `n` along x and y (two as a chart).
    fn triangle(n: f64) -> Vec<[f64; 2]> {
        vec![[0.0, 0.0], [n, 0.0], [0.0, n]]
    }

    #[test]
    fn spans_cover_every_texel_a_triangle_touches() {
        let s = spans(&triangle(4.0), [4.0; 2], 1.0, 0, 64.0);
        // Row r (y in [r, r + 1]) reaches x = 4 − r: texels 0..=3 − r.
        assert_eq!(s.rows, vec![(0, 3), (0, 2), (0, 1), (0, 0)]);
        assert_eq!(s.width, 4);
        // Turned by 90°: (x, y) → (4 − y, x); row r now spans 3 − r..=3.
        let t = spans(&triangle(4.0), [4.0; 2], 1.0, 1, 64.0);
        assert_eq!(t.rows, vec![(0, 3), (1, 3), (2, 3), (3, 3)]);
        // By 180°: the right angle at the bottom right.
        let u = spans(&triangle(4.0), [4.0; 2], 1.0, 2, 64.0);
        assert_eq!(u.rows, vec![(3, 3), (2, 3), (1, 3), (0, 3)]);
        // Past the limit: nothing allocated, and it fits nowhere.
        let far = spans(&triangle(4.0), [4.0; 2], 1e12, 0, 64.0);
        assert!(far.rows.is_empty() && far.width > 64);
    }

    #[test]
    fn two_triangles_share_one_square_and_keep_the_padding() {
        // Two right triangles of legs 20 in a 32² atlas with padding 2: as
        // rectangles (22 × 22 each, in a 28² interior) they cannot both
        // fit, as shapes they do.
        let t = triangle(20.0);
        let charts = [(&t[..], 20.0, 20.0), (&t[..], 20.0, 20.0)];
        let spots = pack_shapes(&charts, 1.0, 2, 32).expect("fits");
        // Every texel either chart touches, in the atlas.
        let mut owner = vec![None; 32 * 32];
        for (c, spot) in spots.iter().enumerate() {
            let s = spans(&t, [20.0; 2], 1.0, spot.turns, 64.0);
            for (r, &(a, b)) in s.rows.iter().enumerate() {
                for x in a..=b {
                    let (x, y) = (spot.origin[0] as i64 + x, spot.origin[1] as i64 + r as i64);
                    assert!(x >= 2 && y >= 2 && x < 30 && y < 30, "{c} at ({x}, {y})");
                    owner[(y * 32 + x) as usize] = Some((c, x, y));
                }
            }
        }
        let cells: Vec<(usize, i64, i64)> = owner.iter().flatten().copied().collect();
        for &(c, x, y) in &cells {
            for &(d, u, v) in &cells {
                if c != d {
                    assert!(
                        (x - u).abs().max((y - v).abs()) > 2,
                        "({x}, {y}) and ({u}, {v})"
                    );
                }
            }
        }
    }
}
