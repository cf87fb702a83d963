//! Splits a scene file into tokens: identifiers, quoted strings, numbers and brackets.
//! `#` starts a comment that runs to the end of the line.

use std::path::Path;

use crate::scene::desc::{Location, SceneError};

#[derive(Clone, Debug, PartialEq)]
pub enum TokenKind {
    /// A bare word: a directive name, or (in the course's dialect) an unquoted value.
    Identifier(String),
    /// The text between double quotes, without them.
    Quoted(String),
    Number(f64),
    OpenBracket,
    CloseBracket,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    pub kind: TokenKind,
    /// 1-based line the token starts on.
    pub line: usize,
}

impl Token {
    /// The token as it would appear in the file, for messages.
    pub fn text(&self) -> String {
        match &self.kind {
            TokenKind::Identifier(word) => word.clone(),
            TokenKind::Quoted(text) => format!("\"{text}\""),
            TokenKind::Number(value) => value.to_string(),
            TokenKind::OpenBracket => "[".into(),
            TokenKind::CloseBracket => "]".into(),
        }
    }
}

/// Characters that end a bare word or a number.
fn is_delimiter(c: char) -> bool {
    c.is_whitespace() || matches!(c, '[' | ']' | '"' | '#')
}

pub fn tokenize(file: &Path, text: &str) -> Result<Vec<Token>, SceneError> {
    let error = |line: usize, message: String| SceneError {
        location: Location::line(file, line),
        message,
    };
    let mut tokens = Vec::new();
    let mut line = 1;
    let mut chars = text.char_indices().peekable();
    while let Some((start, c)) = chars.next() {
        let kind = match c {
            '\n' => {
                line += 1;
                continue;
            }
            c if c.is_whitespace() => continue,
            '#' => {
                while chars.next_if(|&(_, c)| c != '\n').is_some() {}
                continue;
            }
            '[' => TokenKind::OpenBracket,
            ']' => TokenKind::CloseBracket,
            '"' => {
                let mut quoted = String::new();
                loop {
                    match chars.next() {
                        Some((_, '"')) => break,
                        Some((_, '\n')) | None => {
                            return Err(error(line, format!("unterminated string \"{quoted}")));
                        }
                        Some((_, c)) => quoted.push(c),
                    }
                }
                TokenKind::Quoted(quoted)
            }
            _ => {
                let mut end = start + c.len_utf8();
                while let Some((i, c)) = chars.next_if(|&(_, c)| !is_delimiter(c)) {
                    end = i + c.len_utf8();
                }
                let word = &text[start..end];
                if c.is_ascii_digit() || matches!(c, '-' | '+' | '.') {
                    match word.parse::<f64>() {
                        Ok(value) if value.is_finite() => TokenKind::Number(value),
                        _ => return Err(error(line, format!("bad number {word}"))),
                    }
                } else if c.is_alphabetic() || c == '_' {
                    TokenKind::Identifier(word.to_string())
                } else {
                    return Err(error(line, format!("unexpected text {word}")));
                }
            }
        };
        tokens.push(Token { kind, line });
    }
    Ok(tokens)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(text: &str) -> Vec<(TokenKind, usize)> {
        tokenize(Path::new("t.lxs"), text)
            .unwrap()
            .into_iter()
            .map(|t| (t.kind, t.line))
            .collect()
    }

    #[test]
    fn tokens_carry_their_lines_and_comments_are_skipped() {
        use TokenKind::*;
        assert_eq!(
            kinds("AttributeBegin #  \"Area\"\n\"float radius\" [-0.5e1 2]\n[metal2]"),
            vec![
                (Identifier("AttributeBegin".into()), 1),
                (Quoted("float radius".into()), 2),
                (OpenBracket, 2),
                (Number(-5.0), 2),
                (Number(2.0), 2),
                (CloseBracket, 2),
                (OpenBracket, 3),
                (Identifier("metal2".into()), 3),
                (CloseBracket, 3),
            ]
        );
    }

    #[test]
    fn malformed_text_is_an_error_with_its_line() {
        let error = tokenize(Path::new("t.lxs"), "Shape\n\"float radius\" [1.2.3]").unwrap_err();
        assert_eq!(error.to_string(), "t.lxs:2: error: bad number 1.2.3");
        let error = tokenize(Path::new("t.lxs"), "\n\nShape \"sphere").unwrap_err();
        assert_eq!(
            error.to_string(),
            "t.lxs:3: error: unterminated string \"sphere"
        );
        let error = tokenize(Path::new("t.lxs"), "Shape @x").unwrap_err();
        assert_eq!(error.to_string(), "t.lxs:1: error: unexpected text @x");
    }
}
