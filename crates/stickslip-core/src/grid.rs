//! The radial grid shared by r (3D) and x (1D): the paper's uniform nodes r_i = i·a0/N, or
//! nodes graded toward the contact's edge, r_i = a0·(1 − (1 − i/N)^p).
//!
//! Why grade: under a flat-ended stamp the film's shear stress concentrates at the edge
//! r → a0 (a rigid bond would make it singular like 1/√(a0² − r²); the film's compliance
//! smooths it over an edge layer), and the first melting starts there. On the uniform grid the
//! outermost node r = a0 − a0/N moves with N, so the first onset converges at order ≈ 1 (the
//! substrate's displacement varies like (a0 − r)·ln(a0 − r) near the edge), and a thin film's
//! edge layer is not resolved before N ≈ 1000. The power grading puts the outermost node at
//! a0 − a0·N^(−p) and keeps the widest cell (at the axis) p·a0/N: docs/model.md ("The radial
//! grid") has the measured errors the exponent was chosen from.

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// How the nodes are spread over [0, a0).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Grading {
    /// r_i = i·a0/N: the paper's grid (and the only one of its literal scheme).
    #[default]
    Uniform,
    /// r_i = a0·(1 − (1 − i/N)^p), p ≥ 1 (p = 1 is the uniform grid's nodes): cells shrink
    /// toward the edge like (1 − r/a0)^(1 − 1/p).
    Edge {
        /// The exponent p (dimensionless, 1 ≤ p ≤ 4).
        power: f64,
    },
}

impl Grading {
    /// The largest edge exponent allowed (the reference's range; the grid also refuses a
    /// grading whose edge cells fall below [`MIN_EDGE_CELL`]·a0).
    pub const MAX_POWER: f64 = 4.0;

    /// Whether this is the paper's uniform grid.
    pub fn is_uniform(self) -> bool {
        matches!(self, Self::Uniform)
    }
}

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

/// The smallest width, relative to a0, that a graded grid's edge cells may have: below it the
/// node radii's rounding (1e-16·a0) would be a sizeable part of a cell.
pub const MIN_EDGE_CELL: f64 = 1e-12;

/// N nodes on [0, a0): r_0 = 0, graded as [`Grading`] says.
///
/// The last node is r_{N−1} < a0: the contact edge r = a0 itself carries no node (a0 − a0/N
/// on the uniform grid, a0 − a0·N^(−p) on the graded one). Operators decide how to treat the
/// last cell [r_{N−1}, a0] (see [`crate::mdr`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grid {
    radius_m: f64,
    nodes: usize,
    grading: Grading,
}

impl Grid {
    /// The paper's uniform grid of `nodes` ≥ 1 nodes on a contact of radius `radius_m` > 0
    /// (finite).
    pub fn new(radius_m: f64, nodes: usize) -> Result<Self, GridError> {
        Self::graded(radius_m, nodes, Grading::Uniform)
    }

    /// A grid of `nodes` ≥ 1 nodes with `grading` (an edge exponent in [1, 4] whose edge
    /// cells are at least [`MIN_EDGE_CELL`]·a0 wide).
    pub fn graded(radius_m: f64, nodes: usize, grading: Grading) -> Result<Self, GridError> {
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
        if let Grading::Edge { power } = grading {
            if !(1.0..=Grading::MAX_POWER).contains(&power) {
                return Err(GridError::OutOfRange {
                    field: "contact.grading",
                    value: format!("{power}"),
                    allowed: "1 ..= 4",
                });
            }
            // The edge gap a0·N^(−p) is the smallest cell (the last interior one is (2^p − 1)
            // times wider).
            if (nodes as f64).powf(-power) < MIN_EDGE_CELL {
                return Err(GridError::OutOfRange {
                    field: "contact.grading",
                    value: format!("{power} with contact.nodes = {nodes}"),
                    allowed: "N^(-grading) >= 1e-12 (the edge cell a0·N^(-grading) must stay \
                              far above the node radii's rounding): lower the grading or N",
                });
            }
        }
        Ok(Self {
            radius_m,
            nodes,
            grading,
        })
    }

    /// Contact radius a0 in m.
    pub fn radius_m(&self) -> f64 {
        self.radius_m
    }

    /// Number of nodes N.
    pub fn nodes(&self) -> usize {
        self.nodes
    }

    /// How the nodes are spread.
    pub fn grading(&self) -> Grading {
        self.grading
    }

    /// The uniform grid's spacing a0/N in m (on a graded grid, the spacing its nodes would
    /// have without the grading; cells there are [`Self::cell_width_m`]).
    pub fn spacing_m(&self) -> f64 {
        self.radius_m / self.nodes as f64
    }

    /// Width of cell k, [r_k, r_{k+1}], k = 0..N−1, in m (the last cell ends at a0). On the
    /// uniform grid exactly [`Self::spacing_m`], so its operators keep the paper grid's bits.
    pub fn cell_width_m(&self, k: usize) -> f64 {
        match self.grading {
            Grading::Uniform => self.spacing_m(),
            Grading::Edge { .. } => self.node_radius_m(k + 1) - self.node_radius_m(k),
        }
    }

    /// Radius of node i in m, r_i = i·a0/N or a0·(1 − (1 − i/N)^p) (also usable for i = N,
    /// giving a0).
    pub fn node_radius_m(&self, i: usize) -> f64 {
        match self.grading {
            // i·a0/N rather than i·h: exact at i = N and free of accumulated rounding.
            Grading::Uniform => i as f64 * self.radius_m / self.nodes as f64,
            Grading::Edge { power } => {
                let n = self.nodes;
                if i >= n {
                    return self.radius_m;
                }
                // The distance to the edge first: exact in its own scale, so the edge cells
                // keep their relative precision.
                let t = (n - i) as f64 / n as f64;
                self.radius_m - self.radius_m * t.powf(power)
            }
        }
    }

    /// All node radii r_0..r_{N−1} in m.
    pub fn radii_m(&self) -> Vec<f64> {
        (0..self.nodes).map(|i| self.node_radius_m(i)).collect()
    }

    /// Area weights of the nodes for area means ⟨f⟩ = Σ w_i f_i: the annulus between the
    /// midpoints to the neighbouring nodes (from 0 at the axis, to a0 at the last node)
    /// divided by πa0², so the weights sum to 1.
    pub fn area_weights(&self) -> Vec<f64> {
        let n = self.nodes;
        let a0 = self.radius_m;
        (0..n)
            .map(|i| {
                let (lo, hi) = match self.grading {
                    // [r_i − h/2, r_i + h/2]: the midpoints, written as before the grading.
                    Grading::Uniform => (
                        (self.node_radius_m(i) - 0.5 * self.spacing_m()).max(0.0),
                        if i + 1 == n {
                            a0
                        } else {
                            self.node_radius_m(i) + 0.5 * self.spacing_m()
                        },
                    ),
                    Grading::Edge { .. } => (
                        if i == 0 {
                            0.0
                        } else {
                            0.5 * (self.node_radius_m(i - 1) + self.node_radius_m(i))
                        },
                        if i + 1 == n {
                            a0
                        } else {
                            0.5 * (self.node_radius_m(i) + self.node_radius_m(i + 1))
                        },
                    ),
                };
                (hi * hi - lo * lo) / (a0 * a0)
            })
            .collect()
    }

    /// Index of the node nearest to radius `r_m` (clamped into 0..N−1).
    pub fn nearest_node(&self, r_m: f64) -> usize {
        match self.grading {
            Grading::Uniform => {
                let i = (r_m / self.spacing_m()).round();
                if i <= 0.0 {
                    0
                } else {
                    (i as usize).min(self.nodes - 1)
                }
            }
            Grading::Edge { .. } => {
                // The first node at or beyond r, then the nearer of it and its predecessor.
                let (mut lo, mut hi) = (0, self.nodes);
                while lo < hi {
                    let mid = (lo + hi) / 2;
                    if self.node_radius_m(mid) < r_m {
                        lo = mid + 1;
                    } else {
                        hi = mid;
                    }
                }
                if lo == 0 {
                    0
                } else if lo == self.nodes {
                    self.nodes - 1
                } else if r_m - self.node_radius_m(lo - 1) <= self.node_radius_m(lo) - r_m {
                    lo - 1
                } else {
                    lo
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_edge_grading_at_power_one_has_the_uniform_nodes() {
        let u = Grid::new(2e-5, 37).unwrap();
        let g = Grid::graded(2e-5, 37, Grading::Edge { power: 1.0 }).unwrap();
        for i in 0..=37 {
            let (a, b) = (u.node_radius_m(i), g.node_radius_m(i));
            assert!(
                (a - b).abs() <= 4.0 * f64::EPSILON * 2e-5,
                "node {i}: {a} vs {b}"
            );
        }
    }

    #[test]
    fn graded_nodes_increase_and_cluster_at_the_edge() {
        let g = Grid::graded(2e-5, 200, Grading::Edge { power: 2.0 }).unwrap();
        let r = g.radii_m();
        assert_eq!(r[0], 0.0);
        assert!(r.windows(2).all(|w| w[1] > w[0]));
        // Outermost node a0·(1 − N^−2); cells widest at the axis (2a0/N to first order).
        assert!((2e-5 - r[199] - 2e-5 / 40000.0).abs() < 1e-20);
        assert!(g.cell_width_m(0) > g.cell_width_m(100));
        assert!(g.cell_width_m(100) > g.cell_width_m(199));
        let total: f64 = (0..200).map(|k| g.cell_width_m(k)).sum();
        assert!((total - 2e-5).abs() < 1e-18);
    }

    #[test]
    fn area_weights_sum_to_one_on_either_grid() {
        for grading in [Grading::Uniform, Grading::Edge { power: 3.0 }] {
            let g = Grid::graded(1e-5, 150, grading).unwrap();
            let s: f64 = g.area_weights().iter().sum();
            assert!((s - 1.0).abs() < 1e-14, "{grading:?}: {s}");
            assert!(g.area_weights().iter().all(|&w| w > 0.0));
        }
    }

    #[test]
    fn nearest_node_on_a_graded_grid_is_the_nearest() {
        let g = Grid::graded(2e-5, 50, Grading::Edge { power: 2.5 }).unwrap();
        let r = g.radii_m();
        for k in 0..=1000 {
            let x = 2e-5 * k as f64 / 1000.0;
            let best = (0..50)
                .min_by(|&a, &b| (r[a] - x).abs().total_cmp(&(r[b] - x).abs()))
                .unwrap();
            let got = g.nearest_node(x);
            assert!(
                (r[got] - x).abs() <= (r[best] - x).abs(),
                "r = {x}: node {got} vs {best}"
            );
        }
        assert_eq!(g.nearest_node(-1.0), 0);
        assert_eq!(g.nearest_node(1.0), 49);
    }

    #[test]
    fn gradings_outside_their_range_are_refused_naming_the_key() {
        for power in [0.5, 4.5, f64::NAN] {
            let e = Grid::graded(2e-5, 100, Grading::Edge { power }).unwrap_err();
            assert!(e.to_string().contains("contact.grading"), "{e}");
        }
        // 3200^-4 ≈ 1e-14: the edge cell below the rounding guard.
        let e = Grid::graded(2e-5, 3200, Grading::Edge { power: 4.0 }).unwrap_err();
        assert!(e.to_string().contains("N^(-grading)"), "{e}");
        assert!(Grid::graded(2e-5, 3200, Grading::Edge { power: 3.0 }).is_ok());
    }
}
