//! slips.csv: one row per slip of the stamp (docs/model.md#two-scales-meltings-and-slips; the
//! columns of docs/reference.md, section slips.csv).

use super::csv::{NumericCsv, opt, write_cells, write_opt};
use super::table::Table;
use super::{Column, SchemaError};
use crate::slips::Slip;
use std::io::{self, Write};

/// File name.
pub const FILE: &str = "slips.csv";

/// Columns in file order.
pub const COLUMNS: [Column; 12] = [
    Column {
        name: "k",
        unit: "–",
        meaning: "slip number, from 1",
    },
    Column {
        name: "t_start",
        unit: "s",
        meaning: "when the drive force peaked (K·(V0·t − X); F under the rigid drive)",
    },
    Column {
        name: "t_end",
        unit: "s",
        meaning: "when it was lowest, before rising by output.slip_drop·τmax·πa0² again (for a slip still open when the run stopped: its lowest so far)",
    },
    Column {
        name: "f_start",
        unit: "N",
        meaning: "drive force at the start",
    },
    Column {
        name: "f_end",
        unit: "N",
        meaning: "drive force at the end",
    },
    Column {
        name: "drop",
        unit: "N",
        meaning: "f_start − f_end",
    },
    Column {
        name: "x_start",
        unit: "m",
        meaning: "stamp position at the start",
    },
    Column {
        name: "x_end",
        unit: "m",
        meaning: "stamp position at the end",
    },
    Column {
        name: "jump",
        unit: "m",
        meaning: "the stamp's jump, x_end − x_start",
    },
    Column {
        name: "duration",
        unit: "s",
        meaning: "t_end − t_start",
    },
    Column {
        name: "meltings",
        unit: "–",
        meaning: "meltings inside the slip: the one that set it off (the last onset at or before t_start after the previous slip) and every onset up to t_end",
    },
    Column {
        name: "dissipated_energy",
        unit: "J",
        meaning: "energy dissipated from t_start to t_end, every sink of the energy books (events.csv: landau_energy … dashpot_energy); empty for a slip that began before a resume from a checkpoint without the books",
    },
];

/// Columns a file written before the energy books existed has.
const COLUMNS_BEFORE_ENERGY: usize = 11;

/// slips.csv.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Slips(pub Vec<Slip>);

impl Slips {
    /// The slips in order.
    #[must_use]
    pub fn slips(&self) -> &[Slip] {
        &self.0
    }

    /// The columns in file order, by name (`k` and `meltings` as floats).
    #[must_use]
    pub fn columns(&self) -> Vec<(&'static str, Vec<f64>)> {
        let get: [fn(&Slip) -> f64; 12] = [
            |s| s.k as f64,
            |s| s.t_start_s,
            |s| s.t_end_s,
            |s| s.f_start_n,
            |s| s.f_end_n,
            Slip::drop_n,
            |s| s.x_start_m,
            |s| s.x_end_m,
            Slip::jump_m,
            Slip::duration_s,
            |s| s.meltings as f64,
            |s| s.dissipated_energy_j,
        ];
        COLUMNS
            .iter()
            .zip(get)
            .map(|(c, f)| (c.name, self.0.iter().map(f).collect()))
            .collect()
    }
}

impl Table for Slips {
    const FILE: &'static str = FILE;
    /// A directory written before slips existed has none, and reads as no slips.
    const OPTIONAL: bool = true;

    fn write_to<W: Write>(&self, w: &mut W) -> io::Result<()> {
        let names: Vec<&str> = COLUMNS.iter().map(|c| c.name).collect();
        writeln!(w, "{}", names.join(","))?;
        for s in &self.0 {
            write!(w, "{},", s.k)?;
            write_cells(
                w,
                &[
                    s.t_start_s,
                    s.t_end_s,
                    s.f_start_n,
                    s.f_end_n,
                    s.drop_n(),
                    s.x_start_m,
                    s.x_end_m,
                    s.jump_m(),
                    s.duration_s(),
                ],
            )?;
            write!(w, ",{}", s.meltings)?;
            write_opt(w, opt(s.dissipated_energy_j))?;
            writeln!(w)?;
        }
        Ok(())
    }

    /// The derived columns are recomputed, not read.
    fn from_csv(csv: NumericCsv) -> Result<Self, SchemaError> {
        let names: Vec<&str> = COLUMNS.iter().map(|c| c.name).collect();
        csv.expect_header(&names[..COLUMNS_BEFORE_ENERGY], FILE)?;
        let has_energy = csv.header.get(COLUMNS_BEFORE_ENERGY).map(String::as_str)
            == Some(names[COLUMNS_BEFORE_ENERGY]);
        let count = |v: f64, what: &str, line: usize| {
            if v >= 0.0 && v.fract() == 0.0 {
                Ok(v as usize)
            } else {
                Err(SchemaError::new(
                    FILE,
                    Some(line),
                    format!("{what} = {v} is not a count"),
                ))
            }
        };
        let slips = csv
            .rows
            .iter()
            .enumerate()
            .map(|(i, r)| {
                Ok(Slip {
                    k: count(r[0], "k", i + 2)?,
                    t_start_s: r[1],
                    t_end_s: r[2],
                    f_start_n: r[3],
                    f_end_n: r[4],
                    x_start_m: r[6],
                    x_end_m: r[7],
                    meltings: count(r[10], "meltings", i + 2)?,
                    dissipated_energy_j: if has_energy {
                        r[COLUMNS_BEFORE_ENERGY]
                    } else {
                        f64::NAN
                    },
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self(slips))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slips_round_trip_bit_for_bit() {
        let slips = Slips(vec![
            Slip {
                k: 1,
                t_start_s: 0.944_463_558_4,
                t_end_s: 0.988_6,
                f_start_n: 4.662e-4,
                f_end_n: -1.0 / 3.0 * 1e-5,
                x_start_m: 1e-7,
                x_end_m: 1.1e-6,
                meltings: 78,
                dissipated_energy_j: 1.25e-10,
            },
            Slip {
                k: 2,
                t_start_s: 1.775,
                t_end_s: 1.819,
                f_start_n: 3.975e-4,
                f_end_n: 7.59e-5,
                x_start_m: 1.2e-6,
                x_end_m: 2.0e-6,
                meltings: 56,
                dissipated_energy_j: 1.25e-10,
            },
        ]);
        let mut text = Vec::new();
        slips.write_to(&mut text).unwrap();
        let text = String::from_utf8(text).unwrap();
        assert_eq!(Slips::parse(&text).unwrap(), slips);
        assert_eq!(slips.columns()[5].1[0], slips.0[0].drop_n());
        let bad = text.replace(",78,", ",7.5,");
        assert!(Slips::parse(&bad).unwrap_err().message.contains("meltings"));
        // A file written before the energy column reads its slips without energy.
        let old: String = text
            .lines()
            .map(|l| l.rsplit_once(',').unwrap().0.to_string() + "\n")
            .collect();
        let read = Slips::parse(&old).unwrap();
        assert!(read.0.iter().all(|s| s.dissipated_energy_j.is_nan()));
        assert_eq!(read.0[1].meltings, 56);
    }
}
