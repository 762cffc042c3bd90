//! The paper's radial grid r_i = i·a0/N, i = 0..N−1, shared by r (3D) and x (1D).

use thiserror::Error;

/// Error raised when grid parameters are out of range.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GridError {
    /// A parameter is outside its allowed range.
    #[error("{field} = {value} is out of range: {allowed}")]
    OutOfRange {
        /// Name of the offending parameter.
        field: &'static str,
        /// The value given.
        value: String,
        /// The allowed range, in words.
        allowed: &'static str,
    },
}

/// Uniform nodes r_i = i·h, h = a0/N, i = 0..N−1 (the paper's grid).
///
/// The last node is r_{N−1} = a0 − h: the contact edge r = a0 itself carries no node.
/// Operators decide how to treat the last cell [r_{N−1}, a0] (see [`crate::mdr`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    radius_m: f64,
    nodes: usize,
}

impl Grid {
    /// A grid of `nodes` ≥ 1 nodes on a contact of radius `radius_m` > 0 (finite).
    pub fn new(radius_m: f64, nodes: usize) -> Result<Self, GridError> {
        if !(radius_m.is_finite() && radius_m > 0.0) {
            return Err(GridError::OutOfRange {
                field: "contact.radius",
                value: format!("{radius_m:e}"),
                allowed: "finite and > 0 m",
            });
        }
        if nodes == 0 {
            return Err(GridError::OutOfRange {
                field: "contact.nodes",
                value: nodes.to_string(),
                allowed: ">= 1",
            });
        }
        Ok(Self { radius_m, nodes })
    }

    /// Contact radius a0 in m.
    pub fn radius_m(&self) -> f64 {
        self.radius_m
    }

    /// Number of nodes N.
    pub fn nodes(&self) -> usize {
        self.nodes
    }

    /// Node spacing h = a0/N in m.
    pub fn spacing_m(&self) -> f64 {
        self.radius_m / self.nodes as f64
    }

    /// Radius of node i, r_i = i·a0/N in m (also usable for i = N, giving a0).
    pub fn node_radius_m(&self, i: usize) -> f64 {
        // i·a0/N rather than i·h: exact at i = N and free of accumulated rounding.
        i as f64 * self.radius_m / self.nodes as f64
    }

    /// All node radii r_0..r_{N−1} in m.
    pub fn radii_m(&self) -> Vec<f64> {
        (0..self.nodes).map(|i| self.node_radius_m(i)).collect()
    }

    /// Area weights of the nodes for area means ⟨f⟩ = Σ w_i f_i: the annulus
    /// [r_i − h/2, r_i + h/2] ∩ [0, a0] divided by πa0², so the weights sum to 1.
    pub fn area_weights(&self) -> Vec<f64> {
        let n = self.nodes;
        let a0 = self.radius_m;
        (0..n)
            .map(|i| {
                let lo = (self.node_radius_m(i) - 0.5 * self.spacing_m()).max(0.0);
                let hi = if i + 1 == n {
                    a0
                } else {
                    self.node_radius_m(i) + 0.5 * self.spacing_m()
                };
                (hi * hi - lo * lo) / (a0 * a0)
            })
            .collect()
    }

    /// Index of the node nearest to radius `r_m` (clamped into 0..N−1).
    pub fn nearest_node(&self, r_m: f64) -> usize {
        let i = (r_m / self.spacing_m()).round();
        if i <= 0.0 {
            0
        } else {
            (i as usize).min(self.nodes - 1)
        }
    }
}
