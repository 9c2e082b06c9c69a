//! The scanner: HyperFun's lexical rules, byte by byte, with its line and position bookkeeping.
//!
//! A position is a 1-based byte column: a tab counts as one, `\n` starts the next line at 1. Only
//! space, `\n` and `\t` separate tokens in HyperFun; this reader also takes a `\r` just before a
//! `\n` (a file saved on Windows), which HyperFun refuses as an unknown character.

use alloc::string::String;

use super::library::{FUNCTIONS, Function};

/// A place in the text: 1-based line and 1-based byte column.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Pos {
    pub(crate) line: u32,
    pub(crate) col: u32,
}

/// The longest identifier and comment text HyperFun's scanner takes (`MAX_LENGTH_OF_STRING`).
const MAX_LEXEM: usize = 256;

/// A token. Values (a number's, an identifier's text, a function's entry) sit in the [`Scanner`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Tok {
    /// The end of the text (or a NUL byte).
    End,
    /// What HyperFun's scanner calls an illegal token: a malformed number, an unknown character,
    /// an identifier or comment longer than 256 characters, an unterminated string.
    Illegal,
    /// A string constant: no function takes one, so it is always out of place.
    Str,
    Num,
    Ident,
    Func,
    X,
    A,
    S,
    And,
    Or,
    Not,
    Xor,
    Array,
    If,
    Then,
    Else,
    EndIf,
    While,
    Loop,
    EndLoop,
    Pow,
    Plus,
    Minus,
    Tilde,
    Slash,
    NotEqual,
    Star,
    Amp,
    Bar,
    Backslash,
    At,
    Comma,
    Semicolon,
    Assign,
    LParen,
    RParen,
    LBracket,
    RBracket,
    LBrace,
    RBrace,
    Less,
    LessEqual,
    Greater,
    GreaterEqual,
}

/// HyperFun's scanner over a text, one token ahead: the parser reads [`Scanner::tok`] and its
/// values, then calls [`Scanner::next`].
pub(crate) struct Scanner<'a> {
    src: &'a [u8],
    at: usize,
    /// Where the last token ended (HyperFun's `lexem_end_line`, `lexem_end_position`).
    line: u32,
    col: u32,
    /// The current token and where it starts.
    pub(crate) tok: Tok,
    pub(crate) pos: Pos,
    /// The value of a [`Tok::Num`].
    pub(crate) num: f64,
    /// The lower-cased text of a [`Tok::Ident`] or [`Tok::Func`].
    pub(crate) text: String,
    /// The function of a [`Tok::Func`].
    pub(crate) func: &'static Function,
}

impl<'a> Scanner<'a> {
    /// A scanner at the first token of `src`.
    pub(crate) fn new(src: &'a [u8]) -> Self {
        let mut s = Self {
            src,
            at: 0,
            line: 1,
            col: 1,
            tok: Tok::End,
            pos: Pos { line: 1, col: 1 },
            num: 0.0,
            text: String::new(),
            func: &FUNCTIONS[0],
        };
        s.next();
        s
    }

    /// The byte at `i`, NUL past the end (HyperFun reads a NUL-terminated string).
    fn at(&self, i: usize) -> u8 {
        self.src.get(i).copied().unwrap_or(0)
    }

    fn cur(&self) -> u8 {
        self.at(self.at)
    }

    fn bump(&mut self) {
        self.at += 1;
        self.col += 1;
    }

    /// `\r` just before `\n`: our one leniency over HyperFun's delimiters.
    fn crlf(&self, i: usize) -> bool {
        self.at(i) == b'\r' && self.at(i + 1) == b'\n'
    }

    /// Moves to the next token, skipping delimiters and `--` comments.
    pub(crate) fn next(&mut self) {
        loop {
            if !self.token() {
                return;
            }
        }
    }

    /// Scans one token; `true` when it was a comment (to be skipped).
    fn token(&mut self) -> bool {
        loop {
            match self.cur() {
                b' ' | b'\t' => self.bump(),
                b'\n' => {
                    self.at += 1;
                    self.line += 1;
                    self.col = 1;
                }
                b'\r' if self.crlf(self.at) => self.bump(),
                _ => break,
            }
        }
        self.pos = Pos {
            line: self.line,
            col: self.col,
        };
        let c = self.cur();
        let two = |s: &mut Self, second: u8, yes: Tok, no: Tok| {
            s.bump();
            if s.cur() == second {
                s.bump();
                yes
            } else {
                no
            }
        };
        self.tok = match c {
            0 => Tok::End,
            b'-' => {
                self.bump();
                if self.cur() == b'-' {
                    return self.comment();
                }
                Tok::Minus
            }
            b'/' => two(self, b'=', Tok::NotEqual, Tok::Slash),
            b'<' => two(self, b'=', Tok::LessEqual, Tok::Less),
            b'>' => two(self, b'=', Tok::GreaterEqual, Tok::Greater),
            b'"' => self.string(),
            b'0'..=b'9' | b'.' => self.number(),
            c if c.is_ascii_alphabetic() => self.word(),
            c => {
                self.bump();
                match c {
                    b'^' => Tok::Pow,
                    b'+' => Tok::Plus,
                    b'~' => Tok::Tilde,
                    b'*' => Tok::Star,
                    b'&' => Tok::Amp,
                    b'|' => Tok::Bar,
                    b'\\' => Tok::Backslash,
                    b'@' => Tok::At,
                    b',' => Tok::Comma,
                    b';' => Tok::Semicolon,
                    b'=' => Tok::Assign,
                    b'(' => Tok::LParen,
                    b')' => Tok::RParen,
                    b'[' => Tok::LBracket,
                    b']' => Tok::RBracket,
                    b'{' => Tok::LBrace,
                    b'}' => Tok::RBrace,
                    _ => Tok::Illegal,
                }
            }
        };
        false
    }

    /// After `--`: the rest of the line, at most 256 characters, else an illegal token.
    fn comment(&mut self) -> bool {
        self.bump();
        let mut count = 0;
        while self.cur() != b'\n' && self.cur() != 0 && !self.crlf(self.at) && count < MAX_LEXEM {
            self.bump();
            count += 1;
        }
        if self.cur() != b'\n' && self.cur() != 0 && !self.crlf(self.at) {
            self.tok = Tok::Illegal;
            return false;
        }
        true
    }

    /// `"…"` on one line.
    fn string(&mut self) -> Tok {
        self.bump();
        let mut count = 0;
        while !matches!(self.cur(), b'"' | 0 | b'\n') && count < MAX_LEXEM - 1 {
            self.bump();
            count += 1;
        }
        if matches!(self.cur(), 0 | b'\n') {
            return Tok::Illegal;
        }
        self.bump();
        Tok::Str
    }

    /// A number as HyperFun reads it: digits summed one at a time, and an exponent whose sign
    /// applies to its first digit only (`1e-15` is `1e-5`), scaled by `exp(k·ln 10)`.
    fn number(&mut self) -> Tok {
        let digit = |c: u8| f64::from(c - b'0');
        let mut v = 0.0;
        let mut numeric = false;
        if self.cur() != b'.' {
            numeric = true;
            let first = self.cur();
            v = digit(first);
            self.bump();
            if first == b'0' && self.cur().is_ascii_digit() {
                return Tok::Illegal;
            }
            while self.cur().is_ascii_digit() {
                v = v * 10.0 + digit(self.cur());
                self.bump();
            }
        }
        if self.cur() == b'.' {
            self.bump();
            if self.cur().is_ascii_digit() {
                let mut t = 10.0;
                while self.cur().is_ascii_digit() {
                    v += digit(self.cur()) / t;
                    t *= 10.0;
                    self.bump();
                }
            } else if !numeric {
                return Tok::Illegal;
            }
        }
        if matches!(self.cur(), b'e' | b'E') {
            self.bump();
            let mut k = 1.0;
            if self.cur() == b'-' {
                self.bump();
                k = -1.0;
            } else if self.cur() == b'+' {
                self.bump();
            }
            if self.cur() == b'0' || !self.cur().is_ascii_digit() {
                return Tok::Illegal;
            }
            k *= digit(self.cur());
            self.bump();
            while self.cur().is_ascii_digit() {
                k = k * 10.0 + digit(self.cur());
                self.bump();
            }
            v *= libm::exp(k * core::f64::consts::LN_10);
        }
        self.num = v;
        Tok::Num
    }

    /// An identifier, keyword, `x`/`a`/`s` or function name, lower-cased.
    fn word(&mut self) -> Tok {
        self.text.clear();
        let word = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
        while word(self.cur()) && self.text.len() < MAX_LEXEM {
            self.text.push(char::from(self.cur().to_ascii_lowercase()));
            self.bump();
        }
        if word(self.cur()) {
            return Tok::Illegal;
        }
        match self.text.as_str() {
            "a" => Tok::A,
            "s" => Tok::S,
            "x" => Tok::X,
            "and" => Tok::And,
            "or" => Tok::Or,
            "not" => Tok::Not,
            "xor" => Tok::Xor,
            "array" => Tok::Array,
            "if" => Tok::If,
            "then" => Tok::Then,
            "else" => Tok::Else,
            "endif" => Tok::EndIf,
            "while" => Tok::While,
            "loop" => Tok::Loop,
            "endloop" => Tok::EndLoop,
            name => match FUNCTIONS.iter().find(|f| f.name.eq_ignore_ascii_case(name)) {
                Some(f) => {
                    self.func = f;
                    Tok::Func
                }
                None => Tok::Ident,
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::format;
    use alloc::vec::Vec;

    fn tokens(text: &str) -> Vec<(Tok, u32, u32)> {
        let mut s = Scanner::new(text.as_bytes());
        let mut out = Vec::new();
        loop {
            out.push((s.tok, s.pos.line, s.pos.col));
            if s.tok == Tok::End {
                return out;
            }
            s.next();
        }
    }

    fn number(text: &str) -> Option<f64> {
        let s = Scanner::new(text.as_bytes());
        (s.tok == Tok::Num).then_some(s.num)
    }

    #[test]
    #[allow(clippy::excessive_precision)] // HyperFun's `%.17g` output, verbatim
    fn scanner_numbers_read_digit_by_digit_with_the_exponent_quirk() {
        // Values printed by HyperFun's own interpreter (/tmp/hfreal/hfeval, `%.17g`).
        assert_eq!(number("1e-15"), Some(9.999_999_999_999_980_5e-6));
        assert_eq!(number("1e2"), Some(100.000_000_000_000_04));
        assert_eq!(number("2.5e-12"), Some(2.499_999_999_999_995_6e-8));
        assert_eq!(
            number("1e-15").map(|v| v * number("1e15").unwrap_or(0.0)),
            { Some(10_000_000_000.000_04) }
        );
        // `e-XY` is 10^(−10X + Y).
        let e = |k: f64| libm::exp(k * core::f64::consts::LN_10);
        assert_eq!(number("1e-12"), Some(e(-8.0)));
        assert_eq!(number("1e-21"), Some(e(-19.0)));
        assert_eq!(number("1e-10"), Some(e(-10.0)));
        assert_eq!(number("1e+12"), Some(e(12.0)));
        assert_eq!(number("0.5"), Some(0.5));
        assert_eq!(number("5."), Some(5.0));
        assert_eq!(number("0"), Some(0.0));
        assert_eq!(number(".25"), Some(0.25));
        assert_eq!(number("0.1"), Some(0.0 + 1.0 / 10.0));
        assert_eq!(number("123456789012345678901234567890"), {
            let mut v = 1.0;
            for d in "23456789012345678901234567890".bytes() {
                v = v * 10.0 + f64::from(d - b'0');
            }
            Some(v)
        });
        for bad in [
            "05", "00", "1e05", "1e0", "1e+0", "1e", "2ex", ".", ".e2", "1e-",
        ] {
            assert_eq!(number(bad), None, "{bad}");
        }
    }

    #[test]
    fn scanner_positions_count_bytes_and_tabs_as_one() {
        assert_eq!(
            tokens("m(\tx\n  [3]"),
            [
                (Tok::Ident, 1, 1),
                (Tok::LParen, 1, 2),
                (Tok::X, 1, 4),
                (Tok::LBracket, 2, 3),
                (Tok::Num, 2, 4),
                (Tok::RBracket, 2, 5),
                (Tok::End, 2, 6),
            ]
        );
    }

    #[test]
    fn scanner_symbols_keywords_and_comments() {
        let kinds = |t: &str| tokens(t).into_iter().map(|k| k.0).collect::<Vec<_>>();
        assert_eq!(
            kinds("/= <= >= < = > -- a comment\n1--2"),
            [
                Tok::NotEqual,
                Tok::LessEqual,
                Tok::GreaterEqual,
                Tok::Less,
                Tok::Assign,
                Tok::Greater,
                Tok::Num,
                Tok::End
            ]
        );
        assert_eq!(
            kinds("IF Then eLsE endif WHILE loop endloop and or not xor array X A S"),
            [
                Tok::If,
                Tok::Then,
                Tok::Else,
                Tok::EndIf,
                Tok::While,
                Tok::Loop,
                Tok::EndLoop,
                Tok::And,
                Tok::Or,
                Tok::Not,
                Tok::Xor,
                Tok::Array,
                Tok::X,
                Tok::A,
                Tok::S,
                Tok::End
            ]
        );
        assert_eq!(
            kinds("HFSPHERE sin hfa_wave hfR foo _x"),
            [
                Tok::Func,
                Tok::Func,
                Tok::Func,
                Tok::Func,
                Tok::Ident,
                Tok::Illegal,
                Tok::X,
                Tok::End
            ]
        );
        for bad in ["#", "$", "%", "!", ":", "?", "'", "\r", "\"abc", "\u{e9}"] {
            assert_eq!(kinds(bad)[0], Tok::Illegal, "{bad:?}");
        }
        assert_eq!(kinds("\"abc\"")[0], Tok::Str);
        // 256 characters of identifier or comment are taken, 257 are not.
        let long = |n: usize| "b".repeat(n);
        assert_eq!(kinds(&long(256))[0], Tok::Ident);
        assert_eq!(kinds(&long(257))[0], Tok::Illegal);
        assert_eq!(kinds(&format!("--{}\n1", long(256)))[0], Tok::Num);
        assert_eq!(kinds(&format!("--{}\n1", long(257)))[0], Tok::Illegal);
        // A NUL byte ends the text.
        assert_eq!(kinds("1\0 2"), [Tok::Num, Tok::End]);
    }

    #[test]
    fn scanner_takes_crlf_but_not_a_lone_cr() {
        assert_eq!(
            tokens("m\r\n  x -- note\r\n1"),
            [
                (Tok::Ident, 1, 1),
                (Tok::X, 2, 3),
                (Tok::Num, 3, 1),
                (Tok::End, 3, 2)
            ]
        );
        assert_eq!(tokens("m\rx")[1].0, Tok::Illegal);
    }
}
