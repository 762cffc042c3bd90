//! stickslip-validation: the paper's scenes run through the `stickslip` binary, the paper's
//! claims C1–C13 as measured criteria, the hard cases, and the reports of `cargo xtask
//! validate`.
//!
//! Layout: [`sizes`] holds N of the radial scenes, the reduced run's definition and C11's
//! temperatures (imported by the run list, the claims and the reduced check, and importing none
//! of them); [`runner`] holds the run list and runs scenes through the binary (with
//! `stickslip_report::binary`), reading every output file through the run library's schema
//! (`stickslip_run::RunOutput`); [`facts`] reads the scene values and derived numbers of a run
//! from its run.json; [`claims`] (C1–C10) and [`claims_first_order`] (C11–C13, the first-order
//! film) turn outputs into verdicts, [`hysteresis`] stepping C11's imposed-strain loop of a
//! run's film in-process; [`figures`] and [`figures_first_order`] draw the SVGs with
//! `stickslip_report::plot`; [`events_rule`] compares the event lists of the default event
//! settings with the old merge gap; [`report`] and [`findings`] write `reports/index.md` and
//! `reports/summary.json`; [`reduced`] is the small fig2 run whose features the fast test
//! recomputes in-process; [`hard`] runs the hard cases of `validation/hard/` and writes
//! `reports/hard-cases.md`; [`verify_check`] runs `stickslip verify` at a coarse N and checks
//! its uncertainties against the true errors known from much finer runs; [`independent`] runs
//! the independent implementation of `validation/independent/` (Python) beside stickslip and
//! compares their converged values; [`margins`] gives each claim's margin to its threshold;
//! [`sensitivity`] reruns the scenes of C4, C5 and C13 with
//! the melting threshold or the φ floor changed; [`energy`] checks the energy books (fig2 at
//! its defaults, the residual's orders in Δt, the tolerance and N) and writes
//! `reports/energy.json` and its figure; [`staleness`] lists committed reports whose
//! sources changed since the commit they record; [`uncertainty`] repeats the claims' runs at
//! 2N and a tenth of the tolerance and gives each margin its numerical uncertainty;
//! [`validate`] ties it together.
//!
//! Invariants: the claims read output files only (through the schema; C11's loop takes only the
//! film's parameters from a run's run.json); every number in the
//! reports is computed from the runs it describes; the committed reports hold no wall-clock
//! times (those belong to reports/performance.md), so an unchanged validation rewrites them
//! byte for byte.

pub mod advance;
pub mod claims;
pub mod claims_first_order;
pub mod energy;
pub mod events_rule;
pub mod facts;
pub mod figures;
pub mod figures_first_order;
pub mod findings;
pub mod hard;
pub mod hysteresis;
pub mod independent;
pub mod margins;
pub mod reduced;
pub mod report;
pub mod runner;
pub mod sensitivity;
pub mod sizes;
pub mod staleness;
pub mod uncertainty;
pub mod validate;
pub mod verify_check;
