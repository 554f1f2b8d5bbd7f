//! Step 3 of the simplifier: what a collapse costs and what it may not do
//! (W §4.2, App. A; Knodt 2024 §3). The pieces, each its own module:
//!
//! - `quadric.rs`: plane, area and point quadrics and the optimal-point
//!   solve (W App. A, Eq. 14); `stored.rs`: how a run keeps them per vertex;
//! - `cost.rs`: the vertex quadrics with memory (W Eq. 9–13) and the
//!   evaluation of one candidate collapse, which sums the endpoints'
//!   quadrics, adds the memoryless terms of [`collapse_terms`] (each in its
//!   own file behind `term.rs`'s interface), and places the vertex;
//! - `tangent.rs` (Knodt Eq. 2), `symmetry.rs` (Knodt §3.1, Alg. 2) and
//!   `posed.rs` (skinned surfaces in their poses): per-edge and per-pose
//!   planes added to the vertex quadrics;
//! - `attributes/` (Hoppe 1999; Knodt Eq. 6–7): UVs, normals, colors and
//!   skin weights fitted through every collapse;
//! - `current_faces.rs`: the present faces' planes, which rank a collapse
//!   beside the memory quadrics (memoryless, ranking only);
//! - `guards.rs`: the tests a collapse must pass (flips, pinches, links).

pub(crate) mod attributes;
pub(crate) mod boundary_area;
pub(crate) mod cost;
pub(crate) mod crease_area;
pub(crate) mod current_faces;
pub(crate) mod gluing;
pub(crate) mod guards;
#[cfg(test)]
mod guards_oracle;
pub(crate) mod posed;
pub(crate) mod quadric;
pub(crate) mod stored;
pub(crate) mod symmetry;
pub(crate) mod tangent;
pub(crate) mod term;

use std::sync::Arc;

use crate::options::Metric;
use boundary_area::BoundaryArea;
use crease_area::CreaseArea;
use gluing::Gluing;
use term::CollapseTerm;

/// The memoryless terms a run adds to every candidate collapse's quadric,
/// in this order, each where its option turns it on (defaults of
/// [`Metric`]):
///
/// | term | file | option (default) |
/// |---|---|---|
/// | boundary area (W Eq. 15) | `boundary_area.rs` | `boundary_area` (on), `boundary_area_weight` (1) |
/// | crease area | `crease_area.rs` | `crease_area_weight` (1) at `crease_angle` (78°), with the boundary area |
/// | gluing of parts | `gluing.rs` | `gluing_weight` (100) |
///
/// A new term is a file implementing [`CollapseTerm`] and a line here.
/// The terms with memory — face planes (W Eq. 9–13) with the border and
/// crease planes (`border_weight` 1, `crease_weight` 0.25), Knodt's tangent
/// planes (`tangent_weight`, 0; ⅓ in quad mode), the posed planes of skins
/// (`posed.rs`) and the seam planes of attributes — are vertex quadrics,
/// built once in `cost.rs`'s `vertex_quadric_parts` and by the run, and
/// summed by every collapse (W Eq. 13); the attributes' own quadrics are
/// `attributes/`'s.
pub(crate) fn collapse_terms(metric: &Metric) -> Arc<[Box<dyn CollapseTerm>]> {
    let mut terms: Vec<Box<dyn CollapseTerm>> = Vec::new();
    if metric.boundary_area {
        terms.push(Box::new(BoundaryArea {
            weight: metric.boundary_area_weight,
        }));
    }
    if metric.boundary_area && metric.crease_area_weight > 0.0 {
        terms.push(Box::new(CreaseArea {
            weight: metric.boundary_area_weight * metric.crease_area_weight,
            cos: metric.crease_angle.to_radians().cos(),
        }));
    }
    if metric.gluing_weight > 0.0 {
        terms.push(Box::new(Gluing {
            weight: metric.gluing_weight,
        }));
    }
    terms.into()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_list_holds_the_terms_their_options_turn_on_in_order() {
        let names = |m: &Metric| -> Vec<String> {
            collapse_terms(m)
                .iter()
                .map(|t| {
                    format!("{t:?}")
                        .split([' ', '{'])
                        .next()
                        .unwrap_or("")
                        .to_string()
                })
                .collect()
        };
        assert_eq!(
            names(&Metric::default()),
            ["BoundaryArea", "CreaseArea", "Gluing"]
        );
        let no_border = Metric {
            boundary_area: false,
            ..Metric::default()
        };
        // The crease term is the border's term at creases: off with it.
        assert_eq!(names(&no_border), ["Gluing"]);
        let none = Metric {
            crease_area_weight: 0.0,
            gluing_weight: 0.0,
            ..Metric::default()
        };
        assert_eq!(names(&none), ["BoundaryArea"]);
    }
}
