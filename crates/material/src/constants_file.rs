//! The `material` stage's parameter file: the same parameters as the stage
//! takes in YAML, one per line, so one material can serve many pipelines.
//!
//! ```text
//! # the EPDM of lab B (comments start with #; blank lines are skipped)
//! family, ogden
//! mu_pa, 1.2e6, -2.0e5
//! alpha, 2.0, -2.0
//! ```
//!
//! Each line is a parameter's name and its value(s), separated by commas:
//! `family` once, then the family's parameters, each once (a list, Ogden's
//! `mu_pa` and `alpha`, as several values on its line). Read through core's
//! checked reader (a regular file of at most 1 MiB); every error names the
//! file and the line.

use std::path::Path;

use hypercontact_core::param::Choice;
use hypercontact_core::regular_file::{MIB, read_checked_text};
use hypercontact_core::{ParamError, StageError};

use crate::constants::{Constants, Given, NAMES, material};
use crate::material::Material;

/// A parameter file, read: the family and each parameter with its line.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstantsFile {
    family: (Constants, usize),
    /// (name, values, line), in file order.
    values: Vec<(String, Vec<f64>, usize)>,
}

impl Given for ConstantsFile {
    fn get(&self, name: &str) -> Option<&[f64]> {
        (self.values.iter())
            .find(|(n, _, _)| n == name)
            .map(|(_, v, _)| v.as_slice())
    }
}

impl ConstantsFile {
    /// Reads and checks the file at `path`.
    pub fn read(path: &Path) -> Result<Material, StageError> {
        let text = read_checked_text(path, "material parameter files", MIB)
            .map_err(|e| StageError::file(e.path.clone(), e.why.clone()))?;
        let file = Self::parse(&text).map_err(|(line, why)| at_line(path, line, &why))?;
        file.material()
            .map_err(|(line, why)| at_line(path, line, &why))
    }

    /// The material the file gives, or the line and reason it cannot.
    pub fn material(&self) -> Result<Material, (usize, String)> {
        material(self.family.0, self).map_err(|e| (self.line_of(&e), e.to_string()))
    }

    /// The file's lines as names and values, or the first bad line's number
    /// (1-based, as an editor counts) and what is wrong with it.
    pub fn parse(text: &str) -> Result<Self, (usize, String)> {
        let mut family = None;
        let mut values: Vec<(String, Vec<f64>, usize)> = Vec::new();
        for (index, raw) in text.lines().enumerate() {
            let line = index + 1;
            let content = raw.split('#').next().unwrap_or("").trim();
            if content.is_empty() {
                continue;
            }
            let mut fields = content.split(',').map(str::trim);
            let name = fields.next().unwrap_or("");
            let rest: Vec<&str> = fields.collect();
            let seen = values.iter().any(|(n, _, _)| n == name);
            if seen || (name == "family" && family.is_some()) {
                return Err((line, format!("`{name}` is given a second time")));
            }
            if name == "family" {
                family = Some((family_of(&rest).map_err(|why| (line, why))?, line));
            } else if NAMES.contains(&name) {
                let numbers = numbers(name, &rest).map_err(|why| (line, why))?;
                values.push((name.to_owned(), numbers, line));
            } else {
                return Err((line, unknown(name)));
            }
        }
        let family = family.ok_or((1, "no `family` line (e.g. `family, neo-hookean`)".into()))?;
        Ok(Self { family, values })
    }

    /// The line of the parameter an error names (`alpha.1` is `alpha`'s),
    /// or the `family` line.
    fn line_of(&self, e: &ParamError) -> usize {
        let name = e.param.split('.').next().unwrap_or("");
        (self.values.iter())
            .find(|(n, _, _)| n == name)
            .map_or(self.family.1, |(_, _, line)| *line)
    }
}

fn at_line(path: &Path, line: usize, why: &str) -> StageError {
    StageError::file(path, format!("line {line}: {why}"))
}

fn family_of(fields: &[&str]) -> Result<Constants, String> {
    let names = || -> String {
        let all: Vec<&str> = Constants::VARIANTS.iter().map(|v| v.name).collect();
        all.join(", ")
    };
    match fields {
        [name] => Constants::from_name(name)
            .ok_or_else(|| format!("unknown family `{name}` (known: {})", names())),
        _ => Err(format!("`family` takes one name (one of {})", names())),
    }
}

fn numbers(name: &str, fields: &[&str]) -> Result<Vec<f64>, String> {
    if fields.is_empty() {
        return Err(format!("`{name}` has no value"));
    }
    fields
        .iter()
        .map(|text| match text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(format!("`{name}`: `{text}` is not a finite number")),
        })
        .collect()
}

fn unknown(name: &str) -> String {
    if name == "file" {
        return "`file` cannot be given inside a parameter file".into();
    }
    format!(
        "unknown parameter `{name}` (known: family, {})",
        NAMES.join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_err(text: &str) -> (usize, String) {
        ConstantsFile::parse(text)
            .and_then(|f| f.material())
            .unwrap_err()
    }

    #[test]
    fn reads_comments_lists_and_one_value_per_name() {
        let text = "# lab B\n\nfamily, ogden  # 2 terms\nmu_pa, 7e5, -1e5\nalpha,2.0,-2.0\n";
        let file = ConstantsFile::parse(text).unwrap();
        let Material::Hyperelastic(m) = file.material().unwrap() else {
            panic!("ogden is hyperelastic")
        };
        assert_eq!(m.family(), "ogden");
        assert!((m.shear_modulus_pa() - 6e5).abs() < 1e-6);
    }

    #[test]
    fn errors_name_the_line() {
        let (line, why) = parse_err("family, neo-hookean\nmu_pa, 6e5\nc01_pa, 1e4\n");
        assert_eq!(line, 3);
        assert!(
            why.contains("c01_pa") && why.contains("does not take it"),
            "{why}"
        );
        let (line, why) = parse_err("family, gent\n");
        assert_eq!(line, 1);
        assert!(
            why.contains("`gent`") && why.contains("neo-hookean"),
            "{why}"
        );
        let (line, why) = parse_err("family, linear\n\ne_pa, 2 MPa\n");
        assert_eq!(
            (line, why.contains("`2 MPa` is not a finite number")),
            (3, true),
            "{why}"
        );
        let (line, why) = parse_err("family, linear\ne_pa, 2e6\ne_pa, 3e6\n");
        assert_eq!((line, why.contains("second time")), (3, true), "{why}");
        let (line, why) = parse_err("family, ogden\nmu_pa, 1e5, 1e5\nalpha, 2, 0\n");
        assert_eq!(line, 3);
        assert!(why.contains("alpha.1"), "{why}");
        let (line, why) = parse_err("mu_pa, 6e5\n");
        assert!(line == 1 && why.contains("no `family`"), "{why}");
        let (line, why) = parse_err("family, linear\nfile, other.csv\n");
        assert!(line == 2 && why.contains("`file` cannot"), "{why}");
        let (line, why) = parse_err("family, mooney-rivlin\nc10_pa, 1e5\n");
        assert!(line == 1 && why.contains("c01_pa"), "{why}");
    }

    #[test]
    fn read_names_the_file_and_refuses_a_folder() {
        let dir = std::env::temp_dir().join(format!("hc-constants-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("rubber.csv");
        std::fs::write(&path, "family, linear\ne_pa, 2e6\npoisson, 0.49\n").unwrap();
        let Material::Linear(solid) = ConstantsFile::read(&path).unwrap() else {
            panic!("linear")
        };
        assert_eq!((solid.e_pa, solid.poisson), (2e6, 0.49));
        std::fs::write(&path, "family, linear\ne_pa, -2e6\n").unwrap();
        let e = ConstantsFile::read(&path).unwrap_err().to_string();
        assert!(
            e.contains("rubber.csv") && e.contains("line 2") && e.contains("e_pa"),
            "{e}"
        );
        let e = ConstantsFile::read(&dir).unwrap_err().to_string();
        assert!(e.contains("folder"), "{e}");
    }
}
