//! The last step of the simplifier: the collapsed complex back to polygon
//! faces over de-normalized positions, with the maps to the input that
//! attributes, parts and re-baking follow (Knodt 2024: every output face is
//! an input face with merged vertices), and the fitted attributes read at
//! the final positions (Hoppe 1999). `fidelity.rs` and `uv_health.rs`
//! measure an assembled output against its input.

pub(crate) mod fidelity;
pub(crate) mod layers;
pub(crate) mod uv_health;

use wildlod_mesh::Faces;

use crate::collapse::history::History;
use crate::collapse::Collapsed;
use crate::input::{AttributeInput, FittedSkin, FittedStream};
use crate::prepare::complex::NONE;
use crate::prepare::large_polygons::Split;
use crate::report::Report;

/// The simplified polygons and how they map to the input.
#[derive(Clone, Debug, Default)]
pub struct Simplified {
    /// Output positions (input units).
    pub positions: Vec<[f32; 3]>,
    /// Output faces over `positions`; every face is an input face with
    /// merged vertices.
    pub faces: Faces,
    /// For every output face, the input face it is.
    pub face_origin: Vec<u32>,
    /// For every output corner, the input corner it is (so per-corner
    /// attributes can be carried over).
    pub corner_origin: Vec<u32>,
    /// For every input vertex, the output vertex it merged into
    /// (`u32::MAX` when its faces all vanished).
    pub vertex_map: Vec<u32>,
    /// The attribute streams given to [`crate::simplify_with_attributes`], fitted
    /// (in the order given; empty without attributes).
    pub attributes: Vec<FittedStream>,
    /// The skin influences, one set per output vertex, when given.
    pub skin: Option<FittedSkin>,
    /// The morph deltas given ([`crate::AttributeInput::morphs`]), in that
    /// order: per stream, one fitted delta per output vertex.
    pub morphs: Vec<Vec<[f32; 3]>>,
    /// What was reached, and why it stopped.
    pub report: Report,
    /// The collapse history, when [`crate::Record::history`] was set.
    pub history: Option<History>,
}

impl Simplified {
    /// Points the face and corner maps (and the history's face ids) back
    /// at the input faces the `split` pieces came from, and counts the
    /// split in the report.
    pub(crate) fn map_back(&mut self, split: &Split) {
        for f in &mut self.face_origin {
            *f = split.input_face(*f);
        }
        for c in &mut self.corner_origin {
            *c = split.input_corner(*c);
        }
        if let Some(h) = &mut self.history {
            h.map_faces(|f| split.input_face(f));
        }
        self.report.split_polygons = split.polygons;
    }
}

/// The live faces in input order, positions de-normalized (untouched
/// vertices keep their bits in `input_positions`, the input's), and the
/// maps back to the input.
pub(crate) fn assemble(
    run: Collapsed<'_>,
    input_positions: &[[f32; 3]],
    input: &AttributeInput<'_>,
) -> Simplified {
    let c = &run.p.complex;
    let nv = c.pos.len();
    let mut out_id = vec![u32::MAX; nv];
    let mut used = vec![false; nv];
    for f in c.live_faces() {
        for &v in c.face(f) {
            used[v as usize] = true;
        }
    }
    let mut positions = Vec::new();
    for v in 0..nv {
        if !used[v] {
            continue;
        }
        out_id[v] = positions.len() as u32;
        positions.push(if run.moved[v] {
            let p = c.pos[v] * run.p.scale + run.p.center;
            [p.x as f32, p.y as f32, p.z as f32]
        } else {
            // Untouched vertices keep their input bits exactly.
            input_positions[run.p.rep[v] as usize]
        });
    }
    let mut faces = Faces::with_capacity(c.faces.len(), c.slot_vertex.len());
    let mut face_origin = Vec::new();
    let mut corner_origin = Vec::new();
    let mut buf = Vec::new();
    let mut corners = Vec::new();
    let mut riders = c.riders.iter().peekable();
    for f in c.live_faces() {
        buf.clear();
        buf.extend(c.face(f).iter().map(|&v| out_id[v as usize]));
        faces.push(&buf);
        face_origin.push(f);
        let s = c.faces[f as usize].start as usize;
        corners.clear();
        corners.extend((s..s + buf.len()).map(|k| c.corner(k)));
        corner_origin.extend_from_slice(&corners);
        // Its twins, walked the other way round, each with its own
        // input corners where it has them.
        while riders.next_if(|r| r.of < f).is_some() {}
        while let Some(r) = riders.next_if(|r| r.of == f) {
            buf.reverse();
            faces.push(&buf);
            buf.reverse();
            face_origin.push(r.face);
            let start = c.faces[f as usize].start;
            corner_origin.extend(corners.iter().rev().map(|&k| {
                k.checked_sub(start)
                    .and_then(|o| r.corners.get(o as usize))
                    .copied()
                    .filter(|&x| x != NONE)
                    .unwrap_or(k)
            }));
        }
    }
    let root = run.roots();
    let vertex_map = run
        .p
        .weld
        .iter()
        .map(|&w| out_id[root[w as usize] as usize])
        .collect();
    let (attributes, skin, morphs) = match &run.attrs {
        Some(a) => {
            // The run's vertex of every output corner and vertex.
            let mut vertex_of = vec![0u32; positions.len()];
            for (v, &o) in out_id.iter().enumerate() {
                if o != u32::MAX {
                    vertex_of[o as usize] = v as u32;
                }
            }
            let corner_vertex: Vec<u32> = faces
                .indices
                .iter()
                .map(|&o| vertex_of[o as usize])
                .collect();
            (
                a.output(input, &corner_origin, &corner_vertex, &c.pos, &run.moved),
                a.output_skin(&vertex_of, &c.pos),
                a.output_morphs(input, &vertex_of, &c.pos, &run.moved),
            )
        }
        None => (Vec::new(), None, Vec::new()),
    };
    let mut report = run.report;
    report.output_triangles = c.triangles;
    Simplified {
        positions,
        faces,
        face_origin,
        corner_origin,
        vertex_map,
        attributes,
        skin,
        morphs,
        report,
        history: run.history,
    }
}
