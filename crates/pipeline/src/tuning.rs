//! How to simplify, as named settings: the tuning flags of `wildlod
//! simplify`, `lod` and `batch` and the keyword options of the Python
//! package, checked in one place.

use wildlod_simplify::{
    AttributeOptions, Guards, NormalMode, Options, QuadMode, QuadSettings, SeamPolicy,
};

use crate::Error;

/// What happens to attribute seams (UV seams, hard normal edges, color and
/// material borders).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SeamSetting {
    /// Cross a seam only where that costs less than what else is left.
    #[default]
    Penalize,
    /// Never cross seams; the target may be missed.
    Keep,
    /// Let seams move and close like any edge (for re-baked textures).
    Ignore,
}

/// How output normals are made.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum NormalSetting {
    /// Fitted through every collapse, then normalized.
    #[default]
    Fit,
    /// Recomputed from the simplified faces, the input's hard edges kept.
    Recompute,
}

/// How to simplify. Each field is documented on the CLI flag of the same
/// name with dashes (`virtual_radius` is `--virtual-radius`); the defaults
/// are the CLI's.
#[derive(Clone, Debug, PartialEq)]
pub struct Tuning {
    /// Radius of virtual edges relative to the bounding-box diagonal; 0
    /// disables them.
    pub virtual_radius: f64,
    /// Keep topology: no merging of parts, no closing of holes.
    pub keep_topology: bool,
    /// Never move or remove vertices on open borders.
    pub lock_borders: bool,
    /// Largest angle in degrees a face may turn in one collapse, in
    /// (0, 180]; 180 turns the flip guard off. Default 90.
    pub max_normal_turn: f64,
    /// Plain cost order even when the input has quads.
    pub no_quads: bool,
    /// Tolerance under which costs count as equal and are ordered to keep
    /// quads.
    pub quad_epsilon: f64,
    /// Width of the quad ties as a multiple of the input's median initial
    /// collapse deviation, at most `quad_epsilon`
    /// (`QuadSettings::tie_factor`); 0 uses `quad_epsilon` alone.
    pub quad_tie_factor: f64,
    /// How much farther from the input in mean distance a quad-ordered
    /// output may be than the run without the ordering, ≥ 1 (infinite:
    /// not held; `QuadSettings::distance_tolerance`).
    pub quad_tolerance: f64,
    /// Weight of the tangent edge quadrics (Knodt 2024); 0 is off.
    pub tangent_weight: f64,
    /// Soft symmetry λ_sym (Knodt 2024 §3.1); 0 is off.
    pub symmetry: f64,
    /// Rank collapses as if they covered at least this many mean input
    /// faces (`Metric::area_floor`); 0 is off.
    pub area_floor: f64,
    /// Added to the cost of collapses that pinch or fold the surface
    /// (`Metric::pinch_cost`); 0 is off.
    pub pinch_cost: f64,
    /// Caps the pinch cost on parts large enough for the target: thin
    /// parts go once the rest would move by about half this distance
    /// (`Metric::pinch_distance`, relative to the diagonal); 0 is no cap.
    pub pinch_distance: f64,
    /// Face planes weighted by area^A (`Metric::area_exponent`), in [0, 1];
    /// 1 is W's area weighting, 0 every face alike.
    pub area_exponent: f64,
    /// Face planes weigh at least this many mean face areas
    /// (`Metric::face_weight_floor`); 0 is off.
    pub face_weight_floor: f64,
    /// Weight of the planes that hold sharp creases in place, per squared
    /// side length (`Metric::crease_weight`); 0 is off.
    pub crease_weight: f64,
    /// The turn in degrees between two faces above which their shared side
    /// is a crease (`Metric::crease_angle`), in (0, 180).
    pub crease_angle: f64,
    /// Weight of the area swept against creases, relative to the border's
    /// (`Metric::crease_area_weight`); 0 is off.
    pub crease_area_weight: f64,
    /// Weight of the present faces' planes in a collapse's rank, beside
    /// the memory quadrics (`Metric::current_face_weight`); 0 is off, and
    /// so is `classic`.
    pub current_faces: f64,
    /// Classic quadric error simplification (Garland & Heckbert 1997).
    pub classic: bool,
    /// How much UVs steer the collapses.
    pub uv_weight: f64,
    /// How much normals steer the collapses.
    pub normal_weight: f64,
    /// How much vertex colors steer the collapses.
    pub color_weight: f64,
    /// How much skin weights steer the collapses.
    pub skin_weight: f64,
    /// What happens to attribute seams.
    pub seams: SeamSetting,
    /// Weight of the planes that hold seam vertices on their seam.
    pub seam_weight: f64,
    /// How output normals are made.
    pub normals: NormalSetting,
    /// Sweeps of the final refit to the input (`Metric::refit_sweeps`);
    /// 0 is off, and `classic` turns it off.
    pub refit_sweeps: u32,
    /// Keep the reversed copies of faces that cannot be seen
    /// (`Guards::drop_hidden_twins` off).
    pub keep_hidden_twins: bool,
    /// Keep the parts wholly inside a closed, opaque part
    /// (`Guards::drop_enclosed_parts` off).
    pub keep_enclosed_parts: bool,
    /// Let layers (decals and other sheets lying on a part) sink with the
    /// surface under them (`Metric::keep_layers` off); `classic` turns
    /// the layer pass off too.
    pub no_layers: bool,
}

impl Default for Tuning {
    fn default() -> Self {
        let options = Options::default();
        let attributes = AttributeOptions::default();
        Tuning {
            virtual_radius: options.guards.virtual_edge_radius,
            keep_topology: false,
            lock_borders: false,
            // The CLI's default: a quarter turn is a fold, not shading.
            max_normal_turn: 90.0,
            no_quads: false,
            quad_epsilon: QuadSettings::default().epsilon,
            quad_tie_factor: QuadSettings::default().tie_factor,
            quad_tolerance: QuadSettings::default().distance_tolerance,
            tangent_weight: 0.0,
            symmetry: 0.0,
            area_floor: options.metric.area_floor,
            pinch_cost: options.metric.pinch_cost,
            pinch_distance: options.metric.pinch_distance,
            area_exponent: options.metric.area_exponent,
            face_weight_floor: options.metric.face_weight_floor,
            crease_weight: options.metric.crease_weight,
            crease_angle: options.metric.crease_angle,
            crease_area_weight: options.metric.crease_area_weight,
            current_faces: options.metric.current_face_weight,
            classic: false,
            uv_weight: attributes.tex_coord_weight,
            normal_weight: attributes.normal_weight,
            color_weight: attributes.color_weight,
            skin_weight: attributes.skin_weight,
            seams: SeamSetting::Penalize,
            seam_weight: attributes.seam_weight,
            normals: NormalSetting::Fit,
            refit_sweeps: options.metric.refit_sweeps,
            keep_hidden_twins: !options.guards.drop_hidden_twins,
            keep_enclosed_parts: !options.guards.drop_enclosed_parts,
            no_layers: !options.metric.keep_layers,
        }
    }
}

const NON_NEGATIVE: &str = "a non-negative number";

impl Tuning {
    /// The simplifier's options, with every range checked; targets are set
    /// per mesh.
    pub fn options(&self) -> Result<Options, Error> {
        for (name, value) in [
            ("virtual_radius", self.virtual_radius),
            ("quad_epsilon", self.quad_epsilon),
            ("quad_tie_factor", self.quad_tie_factor),
            ("tangent_weight", self.tangent_weight),
            ("symmetry", self.symmetry),
            ("area_floor", self.area_floor),
            ("pinch_cost", self.pinch_cost),
            ("pinch_distance", self.pinch_distance),
            ("face_weight_floor", self.face_weight_floor),
            ("crease_weight", self.crease_weight),
            ("crease_area_weight", self.crease_area_weight),
            ("current_faces", self.current_faces),
            ("uv_weight", self.uv_weight),
            ("normal_weight", self.normal_weight),
            ("color_weight", self.color_weight),
            ("skin_weight", self.skin_weight),
            ("seam_weight", self.seam_weight),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(Error::setting(name, NON_NEGATIVE, value));
            }
        }
        if !(self.area_exponent >= 0.0 && self.area_exponent <= 1.0) {
            return Err(Error::setting(
                "area_exponent",
                "in [0, 1]",
                self.area_exponent,
            ));
        }
        if !(self.crease_angle > 0.0 && self.crease_angle < 180.0) {
            return Err(Error::setting(
                "crease_angle",
                "in (0, 180)",
                self.crease_angle,
            ));
        }
        if self.quad_tolerance.is_nan() || self.quad_tolerance < 1.0 {
            return Err(Error::setting(
                "quad_tolerance",
                "at least 1 (inf: not held)",
                self.quad_tolerance,
            ));
        }
        if !(self.max_normal_turn > 0.0 && self.max_normal_turn <= 180.0) {
            return Err(Error::setting(
                "max_normal_turn",
                "in (0, 180]",
                self.max_normal_turn,
            ));
        }
        let mut options = if self.classic {
            Options::classic_qem()
        } else {
            let mut o = Options::default();
            o.guards.virtual_edge_radius = self.virtual_radius;
            o
        };
        if self.no_quads {
            options.quad.mode = QuadMode::Never;
        }
        options.quad.epsilon = self.quad_epsilon;
        options.quad.tie_factor = self.quad_tie_factor;
        options.quad.distance_tolerance = self.quad_tolerance;
        // Knodt's balance of tangent planes against face planes, when only
        // the symmetry term asks for them.
        let tangent = if self.tangent_weight == 0.0 && self.symmetry > 0.0 {
            1.0 / 3.0
        } else {
            self.tangent_weight
        };
        options.metric.tangent_weight = tangent;
        options.quad.tangent_weight = tangent;
        options.quad.symmetry = self.symmetry;
        options.metric.area_floor = self.area_floor;
        options.metric.pinch_cost = self.pinch_cost;
        options.metric.pinch_distance = self.pinch_distance;
        options.metric.area_exponent = self.area_exponent;
        options.metric.face_weight_floor = self.face_weight_floor;
        options.metric.crease_weight = self.crease_weight;
        options.metric.crease_angle = self.crease_angle;
        options.metric.crease_area_weight = self.crease_area_weight;
        // Classic QEM is the plain algorithm, for comparisons.
        options.metric.current_face_weight = if self.classic {
            0.0
        } else {
            self.current_faces
        };
        options.metric.refit_sweeps = if self.classic { 0 } else { self.refit_sweeps };
        options.guards.drop_hidden_twins = !self.keep_hidden_twins;
        options.guards.drop_enclosed_parts = !self.keep_enclosed_parts;
        options.metric.keep_layers = !self.classic && !self.no_layers;
        options.attributes = AttributeOptions {
            tex_coord_weight: self.uv_weight,
            normal_weight: self.normal_weight,
            color_weight: self.color_weight,
            skin_weight: self.skin_weight,
            seams: match self.seams {
                SeamSetting::Keep => SeamPolicy::Keep,
                SeamSetting::Penalize => SeamPolicy::Penalize,
                SeamSetting::Ignore => SeamPolicy::Ignore,
            },
            normals: match self.normals {
                NormalSetting::Fit => NormalMode::Fit,
                NormalSetting::Recompute => NormalMode::Recompute,
            },
            seam_weight: self.seam_weight,
            ..AttributeOptions::default()
        };
        options.guards = Guards {
            max_normal_turn_degrees: (self.max_normal_turn < 180.0).then_some(self.max_normal_turn),
            keep_topology: self.keep_topology,
            lock_borders: self.lock_borders,
            ..options.guards
        };
        Ok(options)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether `t` is refused with a setting error naming `name`.
    fn refused_as(t: Tuning, name: &str) -> bool {
        matches!(t.options(), Err(Error::Setting { name: n, .. }) if n == name)
    }

    #[test]
    fn out_of_range_settings_are_named() {
        let bad = Tuning {
            uv_weight: -1.0,
            ..Tuning::default()
        };
        match bad.options() {
            Err(Error::Setting { name, .. }) => assert_eq!(name, "uv_weight"),
            other => panic!("expected a setting error, got {other:?}"),
        }
        assert!(refused_as(
            Tuning {
                max_normal_turn: 0.0,
                ..Tuning::default()
            },
            "max_normal_turn"
        ));
    }

    #[test]
    fn area_floor_reaches_the_metric_and_is_range_checked() {
        let o = Tuning {
            area_floor: 1.5,
            ..Tuning::default()
        }
        .options()
        .expect("valid");
        assert_eq!(o.metric.area_floor, 1.5);
        let o = Tuning {
            pinch_cost: 2.0,
            ..Tuning::default()
        }
        .options()
        .expect("valid");
        assert_eq!(o.metric.pinch_cost, 2.0);
        let o = Tuning {
            pinch_distance: 0.2,
            ..Tuning::default()
        }
        .options()
        .expect("valid");
        assert_eq!(o.metric.pinch_distance, 0.2);
        assert!(refused_as(
            Tuning {
                pinch_distance: -0.1,
                ..Tuning::default()
            },
            "pinch_distance"
        ));
        assert_eq!(
            Tuning::default()
                .options()
                .expect("valid")
                .metric
                .area_floor,
            0.0
        );
        assert!(refused_as(
            Tuning {
                area_floor: f64::NAN,
                ..Tuning::default()
            },
            "area_floor"
        ));
    }

    #[test]
    fn layers_are_kept_unless_asked_or_classic() {
        let on = |t: Tuning| t.options().expect("valid").metric.keep_layers;
        assert!(on(Tuning::default()));
        assert!(!on(Tuning {
            no_layers: true,
            ..Tuning::default()
        }));
        assert!(!on(Tuning {
            classic: true,
            ..Tuning::default()
        }));
    }

    #[test]
    fn keep_hidden_twins_turns_the_drop_off() {
        assert!(
            Tuning::default()
                .options()
                .expect("valid")
                .guards
                .drop_hidden_twins
        );
        let o = Tuning {
            keep_hidden_twins: true,
            ..Tuning::default()
        }
        .options()
        .expect("valid");
        assert!(!o.guards.drop_hidden_twins);
    }

    #[test]
    fn keep_enclosed_parts_turns_the_drop_off() {
        assert!(
            Tuning::default()
                .options()
                .expect("valid")
                .guards
                .drop_enclosed_parts
        );
        let o = Tuning {
            keep_enclosed_parts: true,
            ..Tuning::default()
        }
        .options()
        .expect("valid");
        assert!(!o.guards.drop_enclosed_parts);
    }

    #[test]
    fn refit_sweeps_reach_the_options_except_in_classic_mode() {
        assert_eq!(
            Tuning::default().refit_sweeps,
            Options::default().metric.refit_sweeps
        );
        let o = Tuning {
            refit_sweeps: 5,
            ..Tuning::default()
        }
        .options()
        .expect("valid");
        assert_eq!(o.metric.refit_sweeps, 5);
        let o = Tuning {
            refit_sweeps: 5,
            classic: true,
            ..Tuning::default()
        }
        .options()
        .expect("valid");
        assert_eq!(o.metric.refit_sweeps, 0);
    }

    #[test]
    fn area_exponent_reaches_the_metric_and_is_range_checked() {
        let o = Tuning {
            area_exponent: 0.5,
            ..Tuning::default()
        }
        .options()
        .expect("valid");
        assert_eq!(o.metric.area_exponent, 0.5);
        let o = Tuning {
            face_weight_floor: 2.0,
            ..Tuning::default()
        }
        .options()
        .expect("valid");
        assert_eq!(o.metric.face_weight_floor, 2.0);
        assert!(refused_as(
            Tuning {
                face_weight_floor: -1.0,
                ..Tuning::default()
            },
            "face_weight_floor"
        ));
        // Classic QEM keeps the exponent too: it is a weighting, not a term.
        let o = Tuning {
            area_exponent: 0.0,
            classic: true,
            ..Tuning::default()
        }
        .options()
        .expect("valid");
        assert_eq!(o.metric.area_exponent, 0.0);
        for bad in [-0.1, 1.5, f64::NAN] {
            let t = Tuning {
                area_exponent: bad,
                ..Tuning::default()
            };
            assert!(refused_as(t, "area_exponent"), "{bad}");
        }
    }

    #[test]
    fn the_present_faces_weight_reaches_the_metric_is_off_when_classic_and_range_checked() {
        let d = Tuning::default().options().expect("valid");
        assert_eq!(d.metric.current_face_weight, 1.0);
        let o = Tuning {
            current_faces: 0.5,
            ..Tuning::default()
        }
        .options()
        .expect("valid");
        assert_eq!(o.metric.current_face_weight, 0.5);
        let classic = Tuning {
            classic: true,
            ..Tuning::default()
        }
        .options()
        .expect("valid");
        assert_eq!(classic.metric.current_face_weight, 0.0);
        for bad in [-1.0, f64::NAN, f64::INFINITY] {
            let t = Tuning {
                current_faces: bad,
                ..Tuning::default()
            };
            assert!(refused_as(t, "current_faces"), "{bad}");
        }
    }

    #[test]
    fn crease_settings_reach_the_metric_and_are_range_checked() {
        let d = Tuning::default().options().expect("valid");
        assert_eq!(
            d.metric.crease_weight,
            Options::default().metric.crease_weight
        );
        let o = Tuning {
            crease_weight: 1.5,
            crease_angle: 45.0,
            crease_area_weight: 0.0,
            ..Tuning::default()
        }
        .options()
        .expect("valid");
        assert_eq!(
            (
                o.metric.crease_weight,
                o.metric.crease_angle,
                o.metric.crease_area_weight
            ),
            (1.5, 45.0, 0.0)
        );
        for bad in [-1.0, f64::NAN, f64::INFINITY] {
            let t = Tuning {
                crease_weight: bad,
                ..Tuning::default()
            };
            assert!(refused_as(t, "crease_weight"), "{bad}");
            let t = Tuning {
                crease_area_weight: bad,
                ..Tuning::default()
            };
            assert!(refused_as(t, "crease_area_weight"), "{bad}");
        }
        // 0 would make every side a crease, 180 none: both are other flags.
        for bad in [0.0, 180.0, -5.0, f64::NAN] {
            let t = Tuning {
                crease_angle: bad,
                ..Tuning::default()
            };
            assert!(refused_as(t, "crease_angle"), "{bad}");
        }
    }

    #[test]
    fn symmetry_alone_turns_the_tangent_quadrics_on() {
        let o = Tuning {
            symmetry: 0.5,
            ..Tuning::default()
        }
        .options()
        .expect("valid");
        assert!((o.metric.tangent_weight - 1.0 / 3.0).abs() < 1e-12);
        let o = Tuning::default().options().expect("valid");
        assert_eq!(o.metric.tangent_weight, 0.0);
        assert_eq!(o.guards.max_normal_turn_degrees, Some(90.0));
    }
}
