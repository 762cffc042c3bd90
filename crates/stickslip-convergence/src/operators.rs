//! Operator convergence: every MDR operator, both quadratures, against the exact pairs.
//!
//! Errors are relative to the largest value of the exact answer on the grid; the interior norm
//! takes the nodes with 0.25·a0 ≤ r ≤ 0.75·a0 only (away from the axis and the edge, where the
//! two quadratures differ most). The claims asserted in `stickslip-core/tests/mdr_pairs.rs`
//! are the theory column here; this module only measures and tabulates.

use crate::study::{Refined, Study};
use stickslip_core::grid::Grid;
use stickslip_core::mdr::pairs::{self, ExactPair};
use stickslip_core::mdr::{MdrOperators, Quadrature};

/// Contact radius of fig2, m.
pub const A0_M: f64 = 2e-5;

/// Interior norm band, in units of a0.
pub const INTERIOR: (f64, f64) = (0.25, 0.75);

/// The default node counts (ratio 2).
pub const DEFAULT_NODES: [usize; 5] = [125, 250, 500, 1000, 2000];

/// An MDR operator (or a force functional) under test.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Op {
    /// Eq. 13, τ → q.
    Forward,
    /// Eq. 15, q → u3D·G*.
    Back,
    /// back ∘ forward, τ → u3D·G*.
    Compliance,
    /// F = 2π∫τ r dr.
    Force3d,
    /// F = 2∫q dx.
    Force1d,
    /// |F_1D(forward τ) − F_3D(τ)|/F: disagreement of the two forms of Eq. 16.
    ForceAgreement,
}

impl Op {
    /// All operators in table order.
    pub const ALL: [Op; 6] = [
        Op::Forward,
        Op::Back,
        Op::Compliance,
        Op::Force3d,
        Op::Force1d,
        Op::ForceAgreement,
    ];

    /// Name used in tables and JSON.
    pub fn name(&self) -> &'static str {
        match self {
            Op::Forward => "forward",
            Op::Back => "back",
            Op::Compliance => "compliance",
            Op::Force3d => "force_3d",
            Op::Force1d => "force_1d",
            Op::ForceAgreement => "force_agreement",
        }
    }

    /// Whether the result is a field (max and interior norms) or a scalar.
    pub fn is_field(&self) -> bool {
        matches!(self, Op::Forward | Op::Back | Op::Compliance)
    }
}

/// Name of a quadrature in tables.
pub fn quadrature_name(q: Quadrature) -> &'static str {
    match q {
        Quadrature::Literal => "literal",
        Quadrature::Product => "product",
    }
}

/// (max-norm error, interior-norm error) of `op` with `quad` on `pair` at N = `nodes`,
/// relative to the exact answer's largest value (scalars: relative to the exact force).
///
/// # Panics
/// If `nodes` is 0.
#[track_caller]
pub fn errors(pair: &ExactPair, quad: Quadrature, op: Op, nodes: usize) -> (f64, f64) {
    let grid = Grid::new(A0_M, nodes).expect("nodes >= 1");
    let ops = MdrOperators::new(grid, quad);
    let r = grid.radii_m();
    let tau: Vec<f64> = r.iter().map(|&r| (pair.tau)(r, A0_M)).collect();
    let q_exact: Vec<f64> = r.iter().map(|&x| (pair.q)(x, A0_M)).collect();
    let u_exact: Vec<f64> = r.iter().map(|&x| (pair.u3d_g)(x, A0_M)).collect();
    let mut out = vec![0.0; nodes];
    let mut scratch = vec![0.0; nodes];
    let force = (pair.force)(A0_M);
    let exact = match op {
        Op::Forward => {
            ops.forward(&tau, &mut out);
            &q_exact
        }
        Op::Back => {
            ops.back(&q_exact, &mut out);
            &u_exact
        }
        Op::Compliance => {
            ops.compliance(&tau, &mut scratch, &mut out);
            &u_exact
        }
        Op::ForceAgreement => {
            ops.forward(&tau, &mut scratch);
            let e = ((ops.force_1d_n(&scratch) - ops.force_3d_n(&tau)) / force).abs();
            return (e, e);
        }
        Op::Force3d => {
            let e = ((ops.force_3d_n(&tau) - force) / force).abs();
            return (e, e);
        }
        Op::Force1d => {
            let e = ((ops.force_1d_n(&q_exact) - force) / force).abs();
            return (e, e);
        }
    };
    let scale = exact.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let mut max = 0.0_f64;
    let mut interior = 0.0_f64;
    for i in 0..nodes {
        let e = (out[i] - exact[i]).abs() / scale;
        max = max.max(e);
        if r[i] >= INTERIOR.0 * A0_M && r[i] <= INTERIOR.1 * A0_M {
            interior = interior.max(e);
        }
    }
    (max, interior)
}

/// The theoretical order of (pair, quadrature, operator, norm), as claimed and asserted by the
/// core's tests: (order, words). `None` for exact results.
pub fn theory(pair: &str, quad: Quadrature, op: Op, interior: bool) -> (Option<f64>, &'static str) {
    use Op::*;
    let half = (Some(0.5), "1/2");
    let one = (Some(1.0), "1");
    let three_halves = (Some(1.5), "3/2");
    let two = (Some(2.0), "2");
    let none = (Some(0.0), "none");
    let exact = (None, "exact");
    match quad {
        Quadrature::Product => match (pair, op) {
            ("smoother", _) => two,
            ("smooth", Forward | Compliance) if interior => three_halves,
            ("smooth", Forward) => one,
            ("smooth", Back) => two,
            ("smooth", Compliance) => three_halves,
            ("smooth", Force3d) => three_halves,
            ("smooth", Force1d | ForceAgreement) => two,
            ("uniform", Forward | Force3d | Force1d | ForceAgreement) => exact,
            ("uniform", Back | Compliance) if interior => two,
            ("uniform", Back | Compliance) => one,
            ("flat_punch", Forward) if !interior => none,
            ("flat_punch", Back) => exact,
            ("flat_punch", Forward | Compliance | Force3d) => half,
            ("flat_punch", Force1d | ForceAgreement) => one,
            _ => (None, "?"),
        },
        Quadrature::Literal => match (pair, op) {
            (_, Back | Compliance) if !interior => none,
            ("flat_punch", Forward) if !interior => none,
            (_, Forward | Back | Compliance | ForceAgreement) => half,
            ("flat_punch", Force3d) => half,
            ("uniform", Force3d) => one,
            ("smooth", Force3d) => three_halves,
            ("smoother", Force3d) => two,
            ("flat_punch", Force1d) => exact,
            (_, Force1d) => one,
            _ => (None, "?"),
        },
    }
}

/// Every (pair, quadrature, operator, norm) at the node counts `nodes` (ascending, ratio ≥ 1.3).
pub fn study(nodes: &[usize]) -> Vec<Study> {
    let mut out = Vec::new();
    let levels: Vec<f64> = nodes.iter().map(|&n| n as f64).collect();
    for pair in pairs::ALL {
        for quad in [Quadrature::Literal, Quadrature::Product] {
            for op in Op::ALL {
                let errs: Vec<(f64, f64)> =
                    nodes.iter().map(|&n| errors(&pair, quad, op, n)).collect();
                let norms: &[bool] = if op.is_field() {
                    &[false, true]
                } else {
                    &[false]
                };
                for &interior in norms {
                    let e: Vec<f64> = errs
                        .iter()
                        .map(|&(m, i)| if interior { i } else { m })
                        .collect();
                    let norm = if !op.is_field() {
                        "scalar"
                    } else if interior {
                        "interior"
                    } else {
                        "max"
                    };
                    out.push(Study::exact(
                        "operator",
                        op.name(),
                        quadrature_name(quad),
                        Refined::Nodes,
                        levels.clone(),
                        &format!("pair = {}, norm = {norm}", pair.name),
                        "relative",
                        e,
                        theory(pair.name, quad, op, interior),
                    ));
                }
            }
        }
    }
    out
}

/// The pair and norm of an operator study, parsed back from its `fixed` field.
pub fn pair_and_norm(s: &Study) -> (&str, &str) {
    let mut pair = "";
    let mut norm = "";
    for part in s.fixed.split(", ") {
        if let Some(p) = part.strip_prefix("pair = ") {
            pair = p;
        } else if let Some(n) = part.strip_prefix("norm = ") {
            norm = n;
        }
    }
    (pair, norm)
}
