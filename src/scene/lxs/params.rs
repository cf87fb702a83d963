//! Parameter lists: `"type name" [values]` or `"type name" value`, read through typed getters
//! that remember which parameters were used, so that the rest can be reported.

use std::path::{Path, PathBuf};

use glam::Vec3;

use super::tokenizer::{Token, TokenKind};
use crate::scene::desc::{Location, SceneError, SceneWarning};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ParamType {
    Float,
    Int,
    Bool,
    String,
    Color,
    Point,
    Normal,
    Vector,
    Texture,
}

impl ParamType {
    fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "float" => Self::Float,
            "integer" | "int" => Self::Int,
            "bool" => Self::Bool,
            "string" => Self::String,
            "color" | "rgb" => Self::Color,
            "point" => Self::Point,
            "normal" => Self::Normal,
            "vector" => Self::Vector,
            "texture" => Self::Texture,
            _ => return None,
        })
    }
}

#[derive(Clone, Debug, PartialEq)]
enum Values {
    Numbers(Vec<f64>),
    Strings(Vec<String>),
    Bools(Vec<bool>),
}

#[derive(Clone, Debug)]
struct Param {
    /// As written, e.g. `"float fov"`, for messages.
    declaration: String,
    name: String,
    values: Values,
    line: usize,
    used: bool,
}

/// A colour parameter as written: an RGB triple or the name of a texture.
#[derive(Clone, Debug, PartialEq)]
pub enum ColorSource {
    Rgb(Vec3),
    Texture(String),
}

/// Parameters LuxBlend writes that foton has no use for: accepted silently.
const IGNORED: &[&str] = &[
    "architectural",
    "autofocus",
    "cauchyb",
    "discardmipmaps",
    "displayinterval",
    "filtertype",
    "film",
    "filmindex",
    "flipz",
    "flmwriteinterval",
    "fullsweepthreshold",
    "generatetangents",
    "importance",
    "largemutationprob",
    "ldr_clamp_method",
    "lightdepth",
    "lightpathstrategy",
    "lightraycount",
    "lightrrthreshold",
    "eyerrthreshold",
    "lightstrategy",
    "mapping",
    "maxanisotropy",
    "maxconsecrejects",
    "maxprimsperleaf",
    "name",
    "noiseaware",
    "nsamples",
    "outlierrejection_k",
    "restart_resume_flm",
    "shadowraycount",
    "shutterclose",
    "shutteropen",
    "skipfactor",
    "tilecount",
    "usecooldown",
    "writeinterval",
];
const IGNORED_PREFIXES: &[&str] = &["colorspace_", "write_"];

fn is_ignored(name: &str) -> bool {
    IGNORED.contains(&name) || IGNORED_PREFIXES.iter().any(|p| name.starts_with(p))
}

#[derive(Clone, Debug)]
pub struct ParamList {
    file: PathBuf,
    params: Vec<Param>,
}

impl ParamList {
    /// Reads `"type name" value` pairs from `tokens`, all of them.
    pub fn parse(
        file: &Path,
        tokens: &[Token],
        warnings: &mut Vec<SceneWarning>,
    ) -> Result<Self, SceneError> {
        let mut list = ParamList {
            file: file.to_path_buf(),
            params: Vec::new(),
        };
        let mut rest = tokens;
        while let Some((first, after)) = rest.split_first() {
            let TokenKind::Quoted(declaration) = &first.kind else {
                return Err(list.error(
                    first.line,
                    format!("expected a parameter \"type name\", found {}", first.text()),
                ));
            };
            let (values, bare, after) = list.read_values(first, after)?;
            rest = after;
            let words: Vec<&str> = declaration.split_whitespace().collect();
            let [type_name, name] = words[..] else {
                return Err(list.error(
                    first.line,
                    format!("expected a parameter \"type name\", found \"{declaration}\""),
                ));
            };
            let Some(ty) = ParamType::from_name(type_name) else {
                warnings.push(list.warning(
                    first.line,
                    format!("unknown parameter type \"{declaration}\": ignored"),
                ));
                continue;
            };
            let values = list.check_values(first.line, declaration, ty, values, bare, warnings)?;
            list.params.push(Param {
                declaration: declaration.clone(),
                name: name.to_string(),
                values,
                line: first.line,
                used: false,
            });
        }
        Ok(list)
    }

    /// The value after a declaration: `[ ... ]`, or a single number or string. Returns the
    /// values, whether any were bare words, and the tokens after them.
    fn read_values<'t>(
        &self,
        declaration: &Token,
        tokens: &'t [Token],
    ) -> Result<(Vec<TokenKind>, bool, &'t [Token]), SceneError> {
        let missing = || {
            self.error(
                declaration.line,
                format!("{}: value missing", declaration.text()),
            )
        };
        let (first, rest) = tokens.split_first().ok_or_else(missing)?;
        match &first.kind {
            TokenKind::Number(_) | TokenKind::Quoted(_) => {
                Ok((vec![first.kind.clone()], false, rest))
            }
            TokenKind::OpenBracket => {
                let close = rest
                    .iter()
                    .position(|t| t.kind == TokenKind::CloseBracket)
                    .ok_or_else(|| {
                        self.error(
                            first.line,
                            format!("{}: '[' never closed", declaration.text()),
                        )
                    })?;
                let inside = &rest[..close];
                if let Some(nested) = inside.iter().find(|t| t.kind == TokenKind::OpenBracket) {
                    return Err(
                        self.error(nested.line, format!("{}: nested '['", declaration.text()))
                    );
                }
                let bare = inside
                    .iter()
                    .any(|t| matches!(t.kind, TokenKind::Identifier(_)));
                let values = inside.iter().map(|t| t.kind.clone()).collect();
                Ok((values, bare, &rest[close + 1..]))
            }
            _ => Err(missing()),
        }
    }

    /// Checks the values against the declared type and converts them.
    fn check_values(
        &self,
        line: usize,
        declaration: &str,
        ty: ParamType,
        values: Vec<TokenKind>,
        bare: bool,
        warnings: &mut Vec<SceneWarning>,
    ) -> Result<Values, SceneError> {
        let mismatch =
            |expected: &str| self.error(line, format!("\"{declaration}\": expected {expected}"));
        let words = || {
            values
                .iter()
                .map(|v| match v {
                    TokenKind::Quoted(s) | TokenKind::Identifier(s) => Some(s.clone()),
                    _ => None,
                })
                .collect::<Option<Vec<String>>>()
        };
        match ty {
            ParamType::Float
            | ParamType::Int
            | ParamType::Color
            | ParamType::Point
            | ParamType::Normal
            | ParamType::Vector => {
                let numbers = values
                    .iter()
                    .map(|v| match v {
                        TokenKind::Number(n) => Some(*n),
                        _ => None,
                    })
                    .collect::<Option<Vec<f64>>>()
                    .ok_or_else(|| mismatch("numbers"))?;
                if ty == ParamType::Int && numbers.iter().any(|n| n.fract() != 0.0) {
                    warnings.push(self.warning(
                        line,
                        format!("\"{declaration}\" has a fractional value: read as a float"),
                    ));
                }
                Ok(Values::Numbers(numbers))
            }
            ParamType::Bool => words()
                .and_then(|words| {
                    words
                        .iter()
                        .map(|w| match w.as_str() {
                            "true" => Some(true),
                            "false" => Some(false),
                            _ => None,
                        })
                        .collect::<Option<Vec<bool>>>()
                })
                .map(Values::Bools)
                .ok_or_else(|| mismatch("\"true\" or \"false\"")),
            ParamType::String | ParamType::Texture => {
                let strings = words().ok_or_else(|| mismatch("strings"))?;
                if bare && ty == ParamType::String {
                    return Err(mismatch("quoted strings"));
                }
                if bare {
                    warnings.push(self.warning(
                        line,
                        format!("\"{declaration}\": texture name written without quotes"),
                    ));
                }
                Ok(Values::Strings(strings))
            }
        }
    }

    fn error(&self, line: usize, message: String) -> SceneError {
        SceneError {
            location: self.location(line),
            message,
        }
    }

    fn warning(&self, line: usize, message: String) -> SceneWarning {
        SceneWarning {
            location: self.location(line),
            message,
        }
    }

    fn location(&self, line: usize) -> Location {
        Location::line(&self.file, line)
    }

    /// The last parameter called `name`, marked as used.
    fn take(&mut self, name: &str) -> Option<&Param> {
        let param = self.params.iter_mut().rev().find(|p| p.name == name)?;
        param.used = true;
        Some(param)
    }

    fn numbers(&mut self, name: &str) -> Result<Option<(Vec<f64>, String, usize)>, SceneError> {
        let Some(param) = self.take(name) else {
            return Ok(None);
        };
        let (declaration, line) = (param.declaration.clone(), param.line);
        match &param.values {
            Values::Numbers(numbers) => Ok(Some((numbers.clone(), declaration, line))),
            _ => Err(self.error(line, format!("\"{declaration}\": expected numbers"))),
        }
    }

    fn single(&mut self, name: &str) -> Result<Option<(f64, String, usize)>, SceneError> {
        let Some((numbers, declaration, line)) = self.numbers(name)? else {
            return Ok(None);
        };
        match numbers[..] {
            [value] => Ok(Some((value, declaration, line))),
            _ => Err(self.error(
                line,
                format!("\"{declaration}\": {} values, expected 1", numbers.len()),
            )),
        }
    }

    pub fn float(&mut self, name: &str) -> Result<Option<f32>, SceneError> {
        Ok(self.single(name)?.map(|(value, _, _)| value as f32))
    }

    pub fn int(&mut self, name: &str) -> Result<Option<i64>, SceneError> {
        match self.single(name)? {
            None => Ok(None),
            Some((value, _, _)) if value.fract() == 0.0 => Ok(Some(value as i64)),
            Some((value, declaration, line)) => Err(self.error(
                line,
                format!("\"{declaration}\": expected an integer, found {value}"),
            )),
        }
    }

    /// All values of a numeric parameter, `group` at a time (3 for points, 2 for uv).
    pub fn floats(&mut self, name: &str, group: usize) -> Result<Option<Vec<f32>>, SceneError> {
        let Some((numbers, declaration, line)) = self.numbers(name)? else {
            return Ok(None);
        };
        if numbers.len() % group != 0 {
            return Err(self.error(
                line,
                format!(
                    "\"{declaration}\": {} values, not a multiple of {group}",
                    numbers.len()
                ),
            ));
        }
        Ok(Some(numbers.iter().map(|&n| n as f32).collect()))
    }

    /// Non-negative integers, e.g. mesh indices.
    pub fn indices(&mut self, name: &str) -> Result<Option<Vec<u32>>, SceneError> {
        let Some((numbers, declaration, line)) = self.numbers(name)? else {
            return Ok(None);
        };
        let indices = numbers
            .iter()
            .map(|&n| {
                (n.fract() == 0.0 && (0.0..=u32::MAX as f64).contains(&n)).then_some(n as u32)
            })
            .collect::<Option<Vec<u32>>>();
        indices.map(Some).ok_or_else(|| {
            self.error(
                line,
                format!("\"{declaration}\": expected non-negative integers"),
            )
        })
    }

    /// Exactly `N` numbers.
    pub fn array<const N: usize>(&mut self, name: &str) -> Result<Option<[f32; N]>, SceneError> {
        let Some((numbers, declaration, line)) = self.numbers(name)? else {
            return Ok(None);
        };
        let values: Vec<f32> = numbers.iter().map(|&n| n as f32).collect();
        let count = values.len();
        values.try_into().map(Some).map_err(|_| {
            self.error(
                line,
                format!("\"{declaration}\": {count} values, expected {N}"),
            )
        })
    }

    pub fn vec3(&mut self, name: &str) -> Result<Option<Vec3>, SceneError> {
        Ok(self.array::<3>(name)?.map(Vec3::from_array))
    }

    pub fn string(&mut self, name: &str) -> Result<Option<String>, SceneError> {
        let Some(param) = self.take(name) else {
            return Ok(None);
        };
        let (declaration, line) = (param.declaration.clone(), param.line);
        match &param.values {
            Values::Strings(strings) if strings.len() == 1 => Ok(Some(strings[0].clone())),
            _ => Err(self.error(line, format!("\"{declaration}\": expected one string"))),
        }
    }

    pub fn bool(&mut self, name: &str) -> Result<Option<bool>, SceneError> {
        let Some(param) = self.take(name) else {
            return Ok(None);
        };
        let (declaration, line) = (param.declaration.clone(), param.line);
        match &param.values {
            Values::Bools(values) if values.len() == 1 => Ok(Some(values[0])),
            _ => Err(self.error(line, format!("\"{declaration}\": expected one bool"))),
        }
    }

    /// A colour (`"color Kd" [r g b]`, or one grey value) or a texture reference.
    pub fn color(&mut self, name: &str) -> Result<Option<ColorSource>, SceneError> {
        let Some(param) = self.take(name) else {
            return Ok(None);
        };
        let (declaration, line) = (param.declaration.clone(), param.line);
        match &param.values {
            Values::Strings(names) if names.len() == 1 => {
                Ok(Some(ColorSource::Texture(names[0].clone())))
            }
            Values::Numbers(n) if n.len() == 3 => Ok(Some(ColorSource::Rgb(Vec3::new(
                n[0] as f32,
                n[1] as f32,
                n[2] as f32,
            )))),
            Values::Numbers(n) if n.len() == 1 => {
                Ok(Some(ColorSource::Rgb(Vec3::splat(n[0] as f32))))
            }
            _ => Err(self.error(
                line,
                format!("\"{declaration}\": expected a colour [r g b] or one texture name"),
            )),
        }
    }

    /// Marks the parameters called `name` as used, unread; whether there was one.
    pub fn ignore(&mut self, name: &str) -> bool {
        let mut found = false;
        for param in self.params.iter_mut().filter(|p| p.name == name) {
            param.used = true;
            found = true;
        }
        found
    }

    /// Marks every parameter as used: for directives whose parameters foton has no use for.
    pub fn ignore_all(&mut self) {
        for param in &mut self.params {
            param.used = true;
        }
    }

    /// Warns, once each, about the parameters no getter asked for (except LuxBlend's known ones).
    pub fn warn_unused(&self, context: &str, warnings: &mut Vec<SceneWarning>) {
        for param in self
            .params
            .iter()
            .filter(|p| !p.used && !is_ignored(&p.name))
        {
            warnings.push(self.warning(
                param.line,
                format!(
                    "{context}: unknown parameter \"{}\" ignored",
                    param.declaration
                ),
            ));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::lxs::tokenizer::tokenize;

    fn parse(text: &str) -> (Result<ParamList, SceneError>, Vec<SceneWarning>) {
        let mut warnings = Vec::new();
        let tokens = tokenize(Path::new("p.lxs"), text).unwrap();
        (
            ParamList::parse(Path::new("p.lxs"), &tokens, &mut warnings),
            warnings,
        )
    }

    #[test]
    fn typed_getters_read_values() {
        let (list, warnings) = parse(
            "\"float fov\" [45] \"integer xresolution\" 640 \"color Kd\" [0.1 0.2 0.3] \
             \"texture Kr\" \"wood\" \"string filename\" [\"a b.png\"] \
             \"point P\" [0 1 2 3 4 5] \"integer indices\" [0 1 2] \"float screenwindow\" [-1 1 -0.5 0.5]",
        );
        let mut list = list.unwrap();
        assert!(warnings.is_empty());
        assert_eq!(list.float("fov").unwrap(), Some(45.0));
        assert_eq!(list.int("xresolution").unwrap(), Some(640));
        assert_eq!(
            list.color("Kd").unwrap(),
            Some(ColorSource::Rgb(Vec3::new(0.1, 0.2, 0.3)))
        );
        assert_eq!(
            list.color("Kr").unwrap(),
            Some(ColorSource::Texture("wood".into()))
        );
        assert_eq!(list.string("filename").unwrap(), Some("a b.png".into()));
        assert_eq!(
            list.floats("P", 3).unwrap(),
            Some(vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0])
        );
        assert_eq!(list.indices("indices").unwrap(), Some(vec![0, 1, 2]));
        assert_eq!(
            list.array::<4>("screenwindow").unwrap(),
            Some([-1.0, 1.0, -0.5, 0.5])
        );
        assert_eq!(list.float("missing").unwrap(), None);
        let mut unused = Vec::new();
        list.warn_unused("Shape", &mut unused);
        assert!(unused.is_empty());
    }

    #[test]
    fn unused_parameters_are_reported_except_luxblends() {
        let (list, _) =
            parse("\"float bogus\" [1] \"string name\" [\"x\"] \"float colorspace_red\" [0 1]");
        let mut warnings = Vec::new();
        list.unwrap().warn_unused("Shape \"sphere\"", &mut warnings);
        assert_eq!(warnings.len(), 1);
        assert_eq!(
            warnings[0].to_string(),
            "p.lxs:1: warning: Shape \"sphere\": unknown parameter \"float bogus\" ignored"
        );
    }

    #[test]
    fn course_dialect_is_read_with_warnings() {
        let (list, warnings) = parse("\"int roughness\" [0.10]\n\"texture Kd\" [metal2]");
        let mut list = list.unwrap();
        assert_eq!(list.float("roughness").unwrap(), Some(0.1));
        assert_eq!(
            list.color("Kd").unwrap(),
            Some(ColorSource::Texture("metal2".into()))
        );
        assert_eq!(warnings.len(), 2);
        assert!(warnings[0].message.contains("fractional"));
        assert_eq!(warnings[1].location.line, 2);
        assert!(warnings[1].message.contains("without quotes"));
    }

    #[test]
    fn malformed_parameters_are_errors() {
        let message = |text: &str| parse(text).0.unwrap_err().to_string();
        assert_eq!(
            message("\"float fov\""),
            "p.lxs:1: error: \"float fov\": value missing"
        );
        assert_eq!(
            message("\n\"float fov\" [1"),
            "p.lxs:2: error: \"float fov\": '[' never closed"
        );
        assert_eq!(
            message("\"fov\" [1]"),
            "p.lxs:1: error: expected a parameter \"type name\", found \"fov\""
        );
        assert_eq!(
            message("\"float fov\" [\"a\"]"),
            "p.lxs:1: error: \"float fov\": expected numbers"
        );
        assert_eq!(
            message("\"bool b\" [\"yes\"]"),
            "p.lxs:1: error: \"bool b\": expected \"true\" or \"false\""
        );
        let (list, _) = parse("\"float fov\" [1 2] \"point P\" [1 2 3 4] \"integer indices\" [-1]");
        let mut list = list.unwrap();
        assert_eq!(
            list.float("fov").unwrap_err().message,
            "\"float fov\": 2 values, expected 1"
        );
        assert_eq!(
            list.floats("P", 3).unwrap_err().message,
            "\"point P\": 4 values, not a multiple of 3"
        );
        assert_eq!(
            list.indices("indices").unwrap_err().message,
            "\"integer indices\": expected non-negative integers"
        );
    }

    #[test]
    fn unknown_parameter_types_warn() {
        let (list, warnings) = parse("\"spectrum s\" [1 2] \"float a\" 1");
        assert_eq!(list.unwrap().float("a").unwrap(), Some(1.0));
        assert_eq!(
            warnings[0].message,
            "unknown parameter type \"spectrum s\": ignored"
        );
    }
}
