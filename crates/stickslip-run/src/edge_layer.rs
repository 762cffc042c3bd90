//! The contact's edge layer, estimated without a run for `check`: how wide the stress's rise at
//! the edge is, how far the grid's outermost node lies from the edge, and the N at which it
//! lies within the layer's reach.
//!
//! Bonded rigidly to a flat punch, the substrate's stress would be G*·u/(π·√(a0² − r²)); the
//! film in series caps it at its own stiffness a·φ0²/h0 times u. The two meet a distance
//! w = a0/(8ρ²) from the edge, with ρ = π·a0·a·φ0²/(2·G*·h0) the substrate's share of the
//! compliance: the layer over which the first melting's strain rises. On the uniform grid the
//! outermost node is a0/N from the edge, on the graded one a0·N^(−p). Measured on the
//! h0 = 1 nm SFA contact (ρ ≈ 47, reports/convergence.md section 8), the uniform grid's first
//! onset is 5 % off with that node 88 layer widths out, 0.04 % at 11 and 0.01 % at 5.5: within
//! [`REACH_WIDTHS`] widths the first onset is good to a few 1e-4.

use crate::scene::ResolvedScene;
use serde::Serialize;
use stickslip_core::config::{ContactModel, Substrate};
use stickslip_core::grid::Grading;

/// The outermost node counts as resolving the edge layer within this many layer widths.
pub const REACH_WIDTHS: f64 = 10.0;
/// `check` warns when N is below this fraction of the N the layer needs.
pub const WARN_FRACTION: f64 = 0.5;

/// The estimate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EdgeLayer {
    /// ρ = π·a0·a·φ0²/(2·G*·h0) at t = 0.
    pub rho: f64,
    /// The layer's width a0/(8ρ²), m.
    pub width_m: f64,
    /// The outermost node's distance from the edge on the scene's grid, m.
    pub outermost_gap_m: f64,
    /// The N at which that distance is [`REACH_WIDTHS`] layer widths on the scene's grid.
    pub nodes_needed: f64,
    /// The same on the graded grid with the default exponent (3).
    pub nodes_needed_graded: f64,
}

impl EdgeLayer {
    /// The estimate for `scene`: none for a homogeneous contact, a rigid substrate or a film
    /// that starts molten.
    #[must_use]
    pub fn of(scene: &ResolvedScene) -> Option<Self> {
        let c = &scene.config;
        if c.contact.model != ContactModel::Radial || c.contact.substrate != Substrate::Elastic {
            return None;
        }
        let a = c.lubricant.a_pa;
        let phi0 = c.lubricant.solid_phi(0.0, c.temperature.a_coeff_pa(0.0));
        let k = &c.contact;
        let rho = std::f64::consts::PI * k.radius_m * a * phi0 * phi0
            / (2.0 * k.g_eff_pa * k.film_thickness_m);
        if !(rho.is_finite() && rho > 0.0) {
            return None;
        }
        let width_m = k.radius_m / (8.0 * rho * rho);
        let reach = (k.radius_m / (REACH_WIDTHS * width_m)).max(1.0);
        let n = k.nodes as f64;
        let (outermost_gap_m, nodes_needed) = match k.grid {
            Grading::Uniform => (k.radius_m / n, reach),
            Grading::Edge { power } => (k.radius_m * n.powf(-power), reach.powf(1.0 / power)),
        };
        Some(Self {
            rho,
            width_m,
            outermost_gap_m,
            nodes_needed: nodes_needed.ceil(),
            nodes_needed_graded: reach.powf(1.0 / 3.0).ceil(),
        })
    }

    /// Whether the scene's N is far below what the layer needs.
    #[must_use]
    pub fn too_coarse(&self, nodes: usize) -> bool {
        (nodes as f64) < WARN_FRACTION * self.nodes_needed
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    fn scene(name: &str, sets: &[&str]) -> ResolvedScene {
        let path = format!(
            "{}/../../validation/scenes/{name}.toml",
            env!("CARGO_MANIFEST_DIR")
        );
        Scene::from_path(std::path::Path::new(&path), sets).unwrap()
    }

    #[test]
    fn the_thin_film_needs_the_graded_grid_or_many_nodes_and_fig2_neither() {
        // SFA: ρ = π·2e-5·1e6·1.5/(2·1e9·1e-9) ≈ 47.1, w = a0/(8ρ²) ≈ 1.1 nm.
        let sfa = EdgeLayer::of(&scene("sfa", &["contact.grid=uniform"])).unwrap();
        assert!((sfa.rho - 47.12).abs() < 0.01, "{}", sfa.rho);
        assert!((sfa.width_m - 1.126e-9).abs() < 1e-11, "{}", sfa.width_m);
        assert!(sfa.too_coarse(200) && !sfa.too_coarse(1600));
        assert_eq!(sfa.nodes_needed, 1777.0);
        assert_eq!(sfa.nodes_needed_graded, 13.0);
        // The accurate scheme's default grid is the graded one: N = 200 resolves the layer.
        let graded = EdgeLayer::of(&scene("sfa", &[])).unwrap();
        assert_eq!(graded.nodes_needed, 13.0);
        assert!(!graded.too_coarse(200));
        assert!(graded.outermost_gap_m < 1e-11);
        // fig2: ρ ≈ 0.47, the layer is wider than the contact; no N is too coarse.
        let fig2 = EdgeLayer::of(&scene("fig2", &["contact.nodes=25"])).unwrap();
        assert!(!fig2.too_coarse(25), "{fig2:?}");
        // No layer without an elastic radial contact.
        assert!(EdgeLayer::of(&scene("homogeneous", &[])).is_none());
        assert!(EdgeLayer::of(&scene("fig2", &["contact.substrate=rigid"])).is_none());
    }
}
