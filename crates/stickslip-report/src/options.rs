//! The studies' command lines (`cargo xtask convergence`, `bench`, `fit-study`): parsing with
//! clap, and the value checks they share.

use clap::{ArgMatches, CommandFactory, FromArgMatches};
use std::process::ExitCode;

/// Parses `args` (the words after the command) as `bin_name`'s options `T`, with the matches
/// (to tell a given option from its default). `--help` prints and gives exit 0; a bad option
/// prints why and gives exit 2.
///
/// # Errors
/// The exit code to end with, when the options do not parse or help was asked for.
pub fn parse<T: CommandFactory + FromArgMatches>(
    bin_name: &str,
    args: impl IntoIterator<Item = String>,
) -> Result<(T, ArgMatches), ExitCode> {
    let argv = std::iter::once(bin_name.to_string()).chain(args);
    T::command()
        .bin_name(bin_name)
        .try_get_matches_from(argv)
        .and_then(|m| T::from_arg_matches(&m).map(|a| (a, m)))
        .map_err(|e| {
            let _ = e.print();
            if e.use_stderr() {
                ExitCode::from(2)
            } else {
                ExitCode::SUCCESS
            }
        })
}

/// Whether option `id` was given on the command line (not its default).
#[must_use]
pub fn given(matches: &ArgMatches, id: &str) -> bool {
    matches.value_source(id) == Some(clap::parser::ValueSource::CommandLine)
}

/// A count option's value: an integer >= 1.
///
/// # Errors
/// Any other text, in words.
pub fn at_least_one(text: &str) -> Result<usize, String> {
    match text.parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("{text} is not an integer >= 1")),
    }
}

#[cfg(test)]
mod tests {
    use super::at_least_one;

    #[test]
    fn counts_are_integers_of_at_least_one() {
        assert_eq!(at_least_one("3"), Ok(3));
        for bad in ["0", "-1", "x", "1.5", ""] {
            assert!(at_least_one(bad).is_err(), "{bad}");
        }
    }
}
