//! The instruction set the host's marchers run in: the best one the CPU has, or the one the
//! environment variable `VOLSAMPLE_ISA` names (`baseline` or `avx2`), to compare instances.
//! Every instance gives bit-identical results; only the time differs.

use volsample::Isa;

/// The environment variable that forces an instruction set.
pub const VAR: &str = "VOLSAMPLE_ISA";

/// The instruction set `VOLSAMPLE_ISA` names, or the best one this CPU has where it is unset
/// or empty.
///
/// # Errors
/// A message naming the variable, its value and the choices, for a name that is unknown or
/// that this CPU does not have.
pub fn from_env() -> Result<Isa, String> {
    match std::env::var(VAR) {
        Err(std::env::VarError::NotPresent) => Ok(Isa::detect()),
        Err(std::env::VarError::NotUnicode(v)) => Err(format!(
            "{VAR}={v:?} is not a name: use one of {:?}",
            Isa::NAMES
        )),
        Ok(v) if v.trim().is_empty() => Ok(Isa::detect()),
        Ok(v) => Isa::by_name(v.trim()).map_err(|e| {
            let have: Vec<&str> = Isa::available().iter().map(|i| i.name()).collect();
            format!("{VAR}={v}: {e} (this CPU has: {})", have.join(", "))
        }),
    }
}

/// [`from_env`], or the best instruction set where the variable is bad (the CLI checks it
/// at start and stops with the message, so its marchers never see a bad value).
pub fn chosen() -> Isa {
    from_env().unwrap_or_else(|_| Isa::detect())
}
