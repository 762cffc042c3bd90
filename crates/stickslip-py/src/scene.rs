//! `stickslip.Scene`: a validated scene (the resolved scene of the run library), immutable.

use crate::convert;
use crate::errors;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use std::path::PathBuf;
use std::sync::Arc;
use stickslip_run::scene::toml_text;
use stickslip_run::schema::run_info::DerivedReport;
use stickslip_run::{ResolvedScene, Scene};

const NO_OVERRIDES: &[&str] = &[];

/// A validated scene: the keys of a scene file (all quantities SI; docs/reference.md lists
/// them), with every default filled in and every value checked.
///
/// Build one with ``Scene.load(path)``, ``Scene.from_dict(d)`` or ``Scene.from_toml(text)``;
/// ``scene.with_overrides({"contact.nodes": 200})`` gives a new scene (a scene never changes).
/// A bad scene raises ``stickslip.SceneError`` (a ``ValueError``) whose ``key`` names the key.
///
/// Units: Pa (stresses, moduli, ``lubricant.a``, ``temperature.A0``), m (radius, thickness,
/// probe radii), s (times), N/m (``drive.stiffness``), kg (``drive.mass``), m/s
/// (``drive.velocity``), 1/(Pa·s) (``lubricant.gamma``); ``stickslip keys`` lists them all.
#[pyclass(frozen, module = "stickslip", name = "Scene")]
pub struct PyScene {
    /// The scene as the run library resolved it.
    pub inner: Arc<ResolvedScene>,
}

impl PyScene {
    fn new(scene: ResolvedScene) -> Self {
        Self {
            inner: Arc::new(scene),
        }
    }

    fn resolve(table: toml::Table) -> PyResult<Self> {
        Scene::resolve_table(table, NO_OVERRIDES)
            .map(Self::new)
            .map_err(|e| errors::scene(&e))
    }

    /// `table` with the overrides of a Python mapping `{"section.key": value}` applied in
    /// order; `None` removes the key (its default applies again).
    fn apply(mut table: toml::Table, overrides: &Bound<'_, PyAny>) -> PyResult<toml::Table> {
        let Some(items) = convert::mapping_items(overrides)? else {
            return Err(PyTypeError::new_err(format!(
                "overrides must be a dict {{\"section.key\": value}}; got {}",
                overrides.get_type().name()?
            )));
        };
        for (k, v) in items {
            let key: String = k.extract().map_err(|_| {
                PyTypeError::new_err("override keys must be strings such as \"contact.nodes\"")
            })?;
            match convert::to_toml(&v, &key, true)? {
                Some(value) => convert::insert_dotted(&mut table, &key, value),
                None => convert::remove_dotted(&mut table, &key),
            }
            .map_err(|e| errors::scene(&e))?;
        }
        Ok(table)
    }
}

/// `path=` of `Scene.load`: a `TypeError` naming the argument for anything but a path.
fn path_arg(value: &Bound<'_, PyAny>) -> PyResult<PathBuf> {
    crate::args::required_path(value, "path")
}

/// `text=` of `Scene.from_toml`: a `TypeError` naming the argument for anything but a str.
fn toml_text_arg(value: &Bound<'_, PyAny>) -> PyResult<String> {
    value.extract::<String>().map_err(|_| {
        pyo3::exceptions::PyTypeError::new_err(format!(
            "text = {} ({}) is invalid; allowed: the text of a scene file (str)",
            crate::args::shown(value),
            crate::args::type_name(value)
        ))
    })
}

#[pymethods]
impl PyScene {
    /// Reads and validates the scene file at ``path`` (TOML), then applies ``overrides``
    /// (``{"section.key": value}``, like ``--set``) if given.
    ///
    /// Raises ``SceneError`` (with ``.key``) for a bad scene, a file that cannot be read or
    /// is not TOML.
    #[staticmethod]
    #[pyo3(signature = (path, overrides = None))]
    fn load(
        #[pyo3(from_py_with = path_arg)] path: PathBuf,
        overrides: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let text = Scene::read_text(&path).map_err(|e| errors::scene(&e))?;
        let table = Scene::parse_table(&text).map_err(|e| errors::scene(&e))?;
        match overrides {
            Some(o) => Self::resolve(Self::apply(table, o)?),
            None => Self::resolve(table),
        }
    }

    /// A scene from a dict nested like the TOML file
    /// (``{"name": "x", "contact": {"nodes": 200, ...}, ...}``); dotted keys are accepted at
    /// any level (``{"contact.nodes": 200}``). ``None`` values are left out.
    #[staticmethod]
    fn from_dict(d: &Bound<'_, PyAny>) -> PyResult<Self> {
        Self::resolve(convert::scene_table(d)?)
    }

    /// A scene from the text of a scene file (TOML).
    #[staticmethod]
    fn from_toml(#[pyo3(from_py_with = toml_text_arg)] text: String) -> PyResult<Self> {
        let table = Scene::parse_table(&text).map_err(|e| errors::scene(&e))?;
        Self::resolve(table)
    }

    /// A new scene: this one as written with ``overrides`` applied
    /// (``{"contact.nodes": 200, "time.dt": 2e-8}``, like ``--set``; ``None`` removes a key so
    /// its default applies). Defaults derived from other keys (``time.dt_max`` from
    /// ``time.end``, …) follow the new values.
    fn with_overrides(&self, overrides: &Bound<'_, PyAny>) -> PyResult<Self> {
        Self::resolve(Self::apply(self.inner.source.clone(), overrides)?)
    }

    /// The scene as a nested dict: with every default filled in (``resolved=True``, as in
    /// run.json's ``scene``) or as written (``resolved=False``, overrides applied).
    #[pyo3(signature = (*, resolved = true))]
    fn to_dict<'py>(&self, py: Python<'py>, resolved: bool) -> PyResult<Bound<'py, PyDict>> {
        if resolved {
            convert::table_to_py(py, &self.inner.to_table())
        } else {
            convert::table_to_py(py, &self.inner.source)
        }
    }

    /// The scene as TOML text (numbers in shortest round-trip form), with every default
    /// filled in (``resolved=True``) or as written (``resolved=False``);
    /// ``Scene.from_toml(scene.to_toml())`` gives the same scene.
    #[pyo3(signature = (*, resolved = true))]
    fn to_toml(&self, resolved: bool) -> String {
        if resolved {
            self.inner.resolved.to_toml_string()
        } else {
            toml_text::to_toml_string(&self.inner.source)
        }
    }

    /// What ``stickslip check`` reports, as a dict: ``verdict`` (``"run"``, or ``"refused"``
    /// when a run would stop before its first step), ``derived`` (as run.json's: b Pa, A Pa,
    /// eps_c, phi0, omega rad/s, g_eff Pa, nodes, steps_planned, lagged_sweep_contraction,
    /// melting_force N, critical_displacement m, spring_period s, euler_number,
    /// first_onset_estimate s, onset_displacement m (the stamp advance to the contact's
    /// quasi-static melting); with a viscous film also viscous_drag N·s/m, the drag
    /// η·πa0²/h0, and viscous_time s, η·a0/(h0·G*); plus stamp_travel m, the free stamp's
    /// position at time.end),
    /// ``cost`` (probe_steps, seconds_per_step s, steps, seconds s: the estimated wall time of
    /// a run, from a timed probe of about 0.05 s of this scene, ``None`` when the probe's own
    /// pace contradicts the estimate; probe_pace_seconds s: that pace carried to time.end;
    /// basis: how the steps were estimated, or why the time is unknown), ``resolution`` (the
    /// first event at N and 2N: nodes, first_onset_s, f_peak_first_n, relative_change, and
    /// skipped saying why it was not compared; a change above 1 % adds a warning), ``output``
    /// (the expected size: series_rows, probes, profile_rows, bytes, and
    /// interval_for_limit_s, the series interval that keeps it under 100 MB when it would be
    /// larger), ``contact_spring`` (the contact as a linear spring up to the first melting:
    /// x_melt_m, f_melt_n; ``first_onset_estimate`` puts it on the drive; None when the film
    /// starts molten), ``edge_layer`` (where the first melting starts: rho, the substrate's
    /// share of the compliance; width_m, a0/(8·rho²); outermost_gap_m, the outermost node's
    /// distance from the edge; nodes_needed and nodes_needed_graded, the N at which that
    /// distance is 10 widths on this grid and on the graded one; a scene far below adds a
    /// warning; None without an elastic radial contact), ``warnings`` (a list of
    /// ``{"severity": "note" | "warning" | "refusal",
    /// "key", "message"}``), ``name`` and ``scene`` (the resolved scene as a dict).
    ///
    /// Nothing is written; the probe runs with the GIL released.
    fn check<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let scene = Arc::clone(&self.inner);
        let report = py
            .detach(|| stickslip_run::check::check(&scene))
            .map_err(|e| errors::start(&e))?;
        let mut derived = serde_json::to_value(DerivedReport::of(&scene, &report.preflight))
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        if let Some(map) = derived.as_object_mut() {
            map.insert(
                "stamp_travel".to_string(),
                serde_json::json!(report.preflight.stamp_travel_m),
            );
        }
        let json = |v: serde_json::Result<serde_json::Value>| {
            v.map_err(|e| PyValueError::new_err(e.to_string()))
                .and_then(|v| crate::json::json_to_py(py, &v))
        };
        let d = PyDict::new(py);
        d.set_item("name", &scene.name)?;
        d.set_item("verdict", report.verdict().name())?;
        d.set_item("derived", crate::json::json_to_py(py, &derived)?)?;
        d.set_item("cost", json(serde_json::to_value(&report.cost))?)?;
        d.set_item(
            "resolution",
            json(serde_json::to_value(&report.resolution))?,
        )?;
        d.set_item("warnings", json(serde_json::to_value(&report.warnings))?)?;
        d.set_item("edge_layer", json(serde_json::to_value(report.edge))?)?;
        d.set_item("output", json(serde_json::to_value(&report.output))?)?;
        d.set_item(
            "contact_spring",
            json(serde_json::to_value(report.preflight.contact_spring))?,
        )?;
        d.set_item("scene", convert::table_to_py(py, &scene.to_table())?)?;
        Ok(d)
    }

    /// The scene's ``name``.
    #[getter]
    fn name(&self) -> &str {
        &self.inner.name
    }

    /// Number of nodes simulated (``contact.nodes``; 1 for the homogeneous model).
    #[getter]
    fn nodes(&self) -> usize {
        self.inner.config.simulated_nodes()
    }

    /// End time ``time.end``, s.
    #[getter]
    fn end_s(&self) -> f64 {
        self.inner.config.time.end_s
    }

    fn __repr__(&self) -> String {
        format!(
            "<stickslip.Scene {:?}: {} nodes, end {:e} s>",
            self.inner.name,
            self.inner.config.simulated_nodes(),
            self.inner.config.time.end_s
        )
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyScene>()
            .is_ok_and(|o| o.get().inner.resolved == self.inner.resolved)
    }

    fn __copy__(slf: PyRef<'_, Self>) -> PyRef<'_, Self> {
        slf
    }

    fn __deepcopy__<'py>(slf: PyRef<'py, Self>, _memo: &Bound<'py, PyAny>) -> PyRef<'py, Self> {
        slf
    }

    /// Pickles as the scene's TOML text as written.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        let from_toml = py.get_type::<PyScene>().getattr("from_toml")?;
        let args = PyTuple::new(py, [toml_text::to_toml_string(&self.inner.source)])?;
        PyTuple::new(py, [from_toml.into_any(), args.into_any()])
    }
}
