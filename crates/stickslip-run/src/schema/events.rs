//! events.csv: one row per melting event (the columns of docs/reference.md, section events.csv).

use super::csv::{NumericCsv, opt, write_cells, write_num, write_opt};
use super::table::Table;
use super::{Column, SchemaError};
use std::io::{self, Write};
use stickslip_core::sim::energy::EnergyFlows;
use stickslip_core::sim::events::{CycleEnergy, MeltingEvent};

/// File name.
pub const FILE: &str = "events.csv";

/// Columns in file order.
pub const COLUMNS: [Column; 23] = [
    Column {
        name: "k",
        unit: "–",
        meaning: "event number, from 1",
    },
    Column {
        name: "t_onset",
        unit: "s",
        meaning: "first melting of the event (located inside the step by the accurate scheme)",
    },
    Column {
        name: "r_first",
        unit: "m",
        meaning: "radius of the outermost node melted at the onset",
    },
    Column {
        name: "x_onset",
        unit: "m",
        meaning: "stamp position at the onset",
    },
    Column {
        name: "f_peak",
        unit: "N",
        meaning: "largest F since the previous event began",
    },
    Column {
        name: "r_min",
        unit: "m",
        meaning: "innermost radius reached by the melting",
    },
    Column {
        name: "t_center",
        unit: "s",
        meaning: "first time the axis node melted (empty if it did not)",
    },
    Column {
        name: "t_end",
        unit: "s",
        meaning: "when the film had recovered: every node back above the recovery level (empty while open)",
    },
    Column {
        name: "max_melted_fraction",
        unit: "–",
        meaning: "largest area fraction below the melting threshold at one instant (the accurate scheme's melting is instantaneous: → 0 as Δt → 0; see melted_area)",
    },
    Column {
        name: "recovery",
        unit: "–",
        meaning: "largest area-weighted ⟨φ⟩/√(A/a) from this onset to the next (or the end)",
    },
    Column {
        name: "f_mean",
        unit: "N",
        meaning: "time-mean F from this onset to the next (or the end)",
    },
    Column {
        name: "melted_area",
        unit: "–",
        meaning: "area fraction that melted at least once during the event (1 when the front reached the axis)",
    },
    Column {
        name: "dissipated_energy",
        unit: "J",
        meaning: "every sink together from this onset to the next (or the end): landau + reset + sliding + viscous + dashpot (empty for a run resumed from a checkpoint without the energy books)",
    },
    Column {
        name: "drive_work",
        unit: "J",
        meaning: "work of the drive on the stamp over the cycle",
    },
    Column {
        name: "landau_energy",
        unit: "J",
        meaning: "the film's Landau dissipation γ·(∂f/∂φ)² over the cycle",
    },
    Column {
        name: "reset_energy",
        unit: "J",
        meaning: "elastic energy removed by the u0 resets at the cycle's meltings",
    },
    Column {
        name: "sliding_energy",
        unit: "J",
        meaning: "work of the stamp on melted nodes, whose u0 is held (small; can be negative)",
    },
    Column {
        name: "viscous_energy",
        unit: "J",
        meaning: "the film's viscous dissipation (0 without lubricant.viscosity)",
    },
    Column {
        name: "dashpot_energy",
        unit: "J",
        meaning: "the drive's dashpot dissipation (0 without drive.damping)",
    },
    Column {
        name: "temperature_work",
        unit: "J",
        meaning: "free energy the film gained from the change of A(t) (0 at constant temperature)",
    },
    Column {
        name: "noise_work",
        unit: "J",
        meaning: "free energy the phi floor or the noise added to the film",
    },
    Column {
        name: "stored_energy_change",
        unit: "J",
        meaning: "change of the energy stored in spring, stamp, film and substrate over the cycle",
    },
    Column {
        name: "energy_residual",
        unit: "J",
        meaning: "drive_work + temperature_work + noise_work − dissipated_energy − stored_energy_change: the books' error (time stepping and the discrete operators)",
    },
];

/// Columns a file written before the energy books existed has (they read as none there).
const COLUMNS_BEFORE_ENERGY: usize = 12;

/// The energy columns of one event, in file order (NaN without books).
fn energy_cells(e: &MeltingEvent) -> [f64; 11] {
    match &e.energy {
        None => [f64::NAN; 11],
        Some(c) => {
            let f = &c.flows;
            [
                c.dissipated_j(),
                f.drive_work_j,
                f.landau_j,
                f.reset_j,
                f.sliding_j,
                f.viscous_j,
                f.dashpot_j,
                f.temperature_work_j,
                f.noise_work_j,
                c.stored_change_j,
                c.residual_j,
            ]
        }
    }
}

/// The books from the energy cells (none when any is empty).
fn energy_from_cells(r: &[f64]) -> Option<CycleEnergy> {
    if r.len() < 11 || r[..11].iter().any(|v| v.is_nan()) {
        return None;
    }
    Some(CycleEnergy {
        flows: EnergyFlows {
            drive_work_j: r[1],
            landau_j: r[2],
            reset_j: r[3],
            sliding_j: r[4],
            viscous_j: r[5],
            dashpot_j: r[6],
            temperature_work_j: r[7],
            noise_work_j: r[8],
        },
        stored_change_j: r[9],
        residual_j: r[10],
    })
}

/// Columns a file written before `melted_area` existed has (it reads as NaN there).
const COLUMNS_BEFORE_MELTED_AREA: usize = 11;

/// events.csv.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Events(pub Vec<MeltingEvent>);

impl Events {
    /// Events in order.
    #[must_use]
    pub fn events(&self) -> &[MeltingEvent] {
        &self.0
    }

    /// Number of events.
    #[must_use]
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// No events.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Onset times, s.
    #[must_use]
    pub fn onsets_s(&self) -> Vec<f64> {
        self.0.iter().map(|e| e.t_onset_s).collect()
    }

    /// The columns in file order, by name (`k` as a float; none as NaN).
    #[must_use]
    pub fn columns(&self) -> Vec<(&'static str, Vec<f64>)> {
        let get: [fn(&MeltingEvent) -> f64; 23] = [
            |e| e.k as f64,
            |e| e.t_onset_s,
            |e| e.r_first_m,
            |e| e.x_onset_m,
            |e| e.f_peak_n,
            |e| e.r_min_m,
            |e| e.t_center_s.unwrap_or(f64::NAN),
            |e| e.t_end_s.unwrap_or(f64::NAN),
            |e| e.max_melted_fraction,
            |e| e.recovery,
            |e| e.f_mean_n,
            |e| e.melted_area,
            |e| energy_cells(e)[0],
            |e| energy_cells(e)[1],
            |e| energy_cells(e)[2],
            |e| energy_cells(e)[3],
            |e| energy_cells(e)[4],
            |e| energy_cells(e)[5],
            |e| energy_cells(e)[6],
            |e| energy_cells(e)[7],
            |e| energy_cells(e)[8],
            |e| energy_cells(e)[9],
            |e| energy_cells(e)[10],
        ];
        COLUMNS
            .iter()
            .zip(get)
            .map(|(c, f)| (c.name, self.0.iter().map(f).collect()))
            .collect()
    }
}

impl Table for Events {
    const FILE: &'static str = FILE;

    fn write_to<W: Write>(&self, w: &mut W) -> io::Result<()> {
        let names: Vec<&str> = COLUMNS.iter().map(|c| c.name).collect();
        writeln!(w, "{}", names.join(","))?;
        for e in &self.0 {
            write!(w, "{},", e.k)?;
            write_cells(
                w,
                &[e.t_onset_s, e.r_first_m, e.x_onset_m, e.f_peak_n, e.r_min_m],
            )?;
            write_opt(w, e.t_center_s)?;
            write_opt(w, e.t_end_s)?;
            for v in [e.max_melted_fraction, e.recovery, e.f_mean_n, e.melted_area] {
                w.write_all(b",")?;
                write_num(w, v)?;
            }
            for v in energy_cells(e) {
                w.write_all(b",")?;
                if !v.is_nan() {
                    write_num(w, v)?;
                }
            }
            w.write_all(b"\n")?;
        }
        Ok(())
    }

    /// A file written before `melted_area` existed reads it as NaN.
    fn from_csv(csv: NumericCsv) -> Result<Self, SchemaError> {
        let names: Vec<&str> = COLUMNS.iter().map(|c| c.name).collect();
        csv.expect_header(&names[..COLUMNS_BEFORE_MELTED_AREA], FILE)?;
        let has_melted_area = csv
            .header
            .get(COLUMNS_BEFORE_MELTED_AREA)
            .map(String::as_str)
            == Some(names[COLUMNS_BEFORE_MELTED_AREA]);
        let has_energy = csv.header.get(COLUMNS_BEFORE_ENERGY).map(String::as_str)
            == Some(names[COLUMNS_BEFORE_ENERGY]);
        let events = csv
            .rows
            .iter()
            .enumerate()
            .map(|(i, r)| {
                if !(r[0] >= 1.0 && r[0].fract() == 0.0) {
                    return Err(SchemaError::new(
                        FILE,
                        Some(i + 2),
                        format!("k = {} is not an event number", r[0]),
                    ));
                }
                Ok(MeltingEvent {
                    k: r[0] as usize,
                    t_onset_s: r[1],
                    r_first_m: r[2],
                    x_onset_m: r[3],
                    f_peak_n: r[4],
                    r_min_m: r[5],
                    t_center_s: opt(r[6]),
                    t_end_s: opt(r[7]),
                    max_melted_fraction: r[8],
                    recovery: r[9],
                    f_mean_n: r[10],
                    melted_area: if has_melted_area { r[11] } else { f64::NAN },
                    energy: if has_energy {
                        energy_from_cells(&r[COLUMNS_BEFORE_ENERGY..])
                    } else {
                        None
                    },
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self(events))
    }
}
