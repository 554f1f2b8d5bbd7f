//! Texture Chamfer distance (W §5, Table 2, after Yuan et al. 2018): for
//! samples on one surface, the L2 difference between their color and the
//! color of the spatially closest sample of the other surface
//! ([`crate::appearance`] pairs the samples).

/// L2 distance between two RGB colors (components in [0, 1]).
pub(crate) fn color_distance(a: &[f32; 3], b: &[f32; 3]) -> f64 {
    let d2: f32 = (0..3).map(|k| (a[k] - b[k]).powi(2)).sum();
    f64::from(d2).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn color_distance_is_euclidean_over_rgb() {
        assert!((color_distance(&[0.2, 0.4, 0.6], &[0.5, 0.4, 0.2]) - 0.5).abs() < 1e-7);
        assert_eq!(color_distance(&[0.3; 3], &[0.3; 3]), 0.0);
    }
}
