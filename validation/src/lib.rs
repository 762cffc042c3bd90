//! stickslip-validation: the paper's scenes and claims checks (filled by the validation issue).
