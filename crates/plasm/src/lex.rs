//! Tokens with their places in the source.

use crate::{Error, ErrorKind, Span};

/// One token.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Tok {
    Num(f64),
    /// A name as written (names are case-insensitive; the parser folds them).
    Name(String),
    Def,
    Where,
    End,
    LParen,
    RParen,
    LBrack,
    RBrack,
    Lt,
    Gt,
    Comma,
    Semi,
    Colon,
    ColonColon,
    Tilde,
    Eq,
    Plus,
    Minus,
    Star,
    Slash,
    Pow,
    DotDot,
    Eof,
}

impl Tok {
    /// How the token reads in an error message.
    pub(crate) fn describe(&self) -> String {
        match self {
            Tok::Num(x) => format!("the number {x}"),
            Tok::Name(n) => format!("`{n}`"),
            Tok::Def => "`DEF`".into(),
            Tok::Where => "`WHERE`".into(),
            Tok::End => "`END`".into(),
            Tok::Eof => "the end of the script".into(),
            other => format!("`{}`", other.symbol()),
        }
    }

    /// The text of a punctuation token.
    pub(crate) fn symbol(&self) -> &'static str {
        match self {
            Tok::LParen => "(",
            Tok::RParen => ")",
            Tok::LBrack => "[",
            Tok::RBrack => "]",
            Tok::Lt => "<",
            Tok::Gt => ">",
            Tok::Comma => ",",
            Tok::Semi => ";",
            Tok::Colon => ":",
            Tok::ColonColon => "::",
            Tok::Tilde => "~",
            Tok::Eq => "=",
            Tok::Plus => "+",
            Tok::Minus => "-",
            Tok::Star => "*",
            Tok::Slash => "/",
            Tok::Pow => "**",
            Tok::DotDot => "..",
            _ => "",
        }
    }
}

/// Splits `src` into tokens; the last is [`Tok::Eof`]. Comments run from `%` to the next `%` on
/// the same line or to the end of the line.
pub(crate) fn lex(src: &str, first_line: u32) -> Result<Vec<(Tok, Span)>, Error> {
    let mut out = Vec::new();
    let chars: Vec<(usize, char)> = src.char_indices().collect();
    let (mut i, mut line, mut col) = (0usize, first_line, 1u32);
    let at = |i: usize, line: u32, col: u32, len: usize| Span {
        start: chars.get(i).map_or(src.len(), |c| c.0) as u32,
        end: chars.get(i + len).map_or(src.len(), |c| c.0) as u32,
        line,
        col,
    };
    while i < chars.len() {
        let c = chars[i].1;
        let next = chars.get(i + 1).map(|c| c.1);
        if c == '\n' {
            i += 1;
            line += 1;
            col = 1;
            continue;
        }
        if c.is_whitespace() {
            i += 1;
            col += 1;
            continue;
        }
        if c == '%' {
            i += 1;
            col += 1;
            while i < chars.len() && chars[i].1 != '\n' {
                let done = chars[i].1 == '%';
                i += 1;
                col += 1;
                if done {
                    break;
                }
            }
            continue;
        }
        let start = i;
        let (tok, len) = if c.is_ascii_digit()
            || (c == '.' && next.is_some_and(|n| n.is_ascii_digit()))
        {
            let mut j = i;
            let digits = |j: &mut usize| {
                while *j < chars.len() && chars[*j].1.is_ascii_digit() {
                    *j += 1;
                }
            };
            digits(&mut j);
            // A '.' is a decimal point only before a digit: `0..n` is a range.
            if j + 1 < chars.len() && chars[j].1 == '.' && chars[j + 1].1.is_ascii_digit() {
                j += 1;
                digits(&mut j);
            }
            if j < chars.len() && matches!(chars[j].1, 'e' | 'E') {
                let mut k = j + 1;
                if k < chars.len() && matches!(chars[k].1, '+' | '-') {
                    k += 1;
                }
                if k < chars.len() && chars[k].1.is_ascii_digit() {
                    j = k;
                    digits(&mut j);
                }
            }
            let text: String = chars[i..j].iter().map(|c| c.1).collect();
            let value: f64 = text.parse().map_err(|_| {
                Error::new(
                    ErrorKind::Syntax,
                    at(i, line, col, j - i),
                    format!("`{text}` is not a number"),
                )
            })?;
            if !value.is_finite() {
                return Err(Error::new(
                    ErrorKind::Syntax,
                    at(i, line, col, j - i),
                    format!("`{text}` is too large a number"),
                ));
            }
            (Tok::Num(value), j - i)
        } else if c.is_alphabetic() || c == '_' || c == '#' {
            let mut j = i + 1;
            if c != '#' {
                while j < chars.len() && (chars[j].1.is_alphanumeric() || chars[j].1 == '_') {
                    j += 1;
                }
            }
            let text: String = chars[i..j].iter().map(|c| c.1).collect();
            let tok = match text.to_ascii_uppercase().as_str() {
                "DEF" => Tok::Def,
                "WHERE" => Tok::Where,
                "END" => Tok::End,
                _ => Tok::Name(text),
            };
            (tok, j - i)
        } else {
            let two = next.map(|n| [c, n]);
            match two {
                Some([':', ':']) => (Tok::ColonColon, 2),
                Some(['*', '*']) => (Tok::Pow, 2),
                Some(['.', '.']) => (Tok::DotDot, 2),
                _ => {
                    let tok = match c {
                        '(' => Tok::LParen,
                        ')' => Tok::RParen,
                        '[' => Tok::LBrack,
                        ']' => Tok::RBrack,
                        '<' => Tok::Lt,
                        '>' => Tok::Gt,
                        ',' => Tok::Comma,
                        ';' => Tok::Semi,
                        ':' => Tok::Colon,
                        '~' => Tok::Tilde,
                        '=' => Tok::Eq,
                        '+' => Tok::Plus,
                        '-' => Tok::Minus,
                        '*' => Tok::Star,
                        '/' => Tok::Slash,
                        _ => {
                            let what = if c == '\'' || c == '"' {
                                "strings are not part of this PLaSM subset".to_string()
                            } else {
                                format!("unexpected character `{c}`")
                            };
                            return Err(Error::new(ErrorKind::Syntax, at(i, line, col, 1), what));
                        }
                    };
                    (tok, 1)
                }
            }
        };
        out.push((tok, at(start, line, col, len)));
        i += len;
        col += len as u32;
    }
    out.push((Tok::Eof, at(chars.len(), line, col, 0)));
    Ok(out)
}
