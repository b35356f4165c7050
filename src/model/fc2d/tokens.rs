//! The tokens of a problem file, each with its line, and the reading of
//! integers and reals with the error naming the file, line and token.

use super::Fc2dError;
use std::path::Path;

/// A cursor over the whitespace-separated tokens of a file, each with its
/// line.
pub(super) struct Tokens<'a> {
    toks: Vec<(&'a str, usize)>,
    pos: usize,
    last_line: usize,
    path: &'a Path,
}

impl<'a> Tokens<'a> {
    /// The tokens of `text`; `path` names the file in errors.
    pub(super) fn new(text: &'a str, path: &'a Path) -> Self {
        let mut toks = Vec::new();
        let mut last_line = 1;
        for (l, line) in text.lines().enumerate() {
            last_line = l + 1;
            toks.extend(line.split_whitespace().map(|t| (t, l + 1)));
        }
        Tokens {
            toks,
            pos: 0,
            last_line,
            path,
        }
    }

    /// The tokens not read yet.
    pub(super) fn left(&self) -> usize {
        self.toks.len() - self.pos
    }

    /// The error at the next token (or at the end of the file).
    pub(super) fn error_here(&self, expected: impl Into<String>) -> Fc2dError {
        match self.toks.get(self.pos) {
            Some(&(t, l)) => self.error_at(t, l, expected),
            None => self.error_end(expected),
        }
    }

    /// The error at a token already read.
    pub(super) fn error_at(
        &self,
        token: &str,
        line: usize,
        expected: impl Into<String>,
    ) -> Fc2dError {
        let token: String = if token.chars().count() > 40 {
            token.chars().take(40).chain("…".chars()).collect()
        } else {
            token.to_string()
        };
        Fc2dError {
            path: self.path.to_path_buf(),
            line,
            token: Some(token),
            expected: expected.into(),
        }
    }

    fn error_end(&self, expected: impl Into<String>) -> Fc2dError {
        Fc2dError {
            path: self.path.to_path_buf(),
            line: self.last_line,
            token: None,
            expected: expected.into(),
        }
    }

    /// The next token and its line, or the end-of-file error.
    pub(super) fn next(&mut self, expected: &str) -> Result<(&'a str, usize), Fc2dError> {
        match self.toks.get(self.pos) {
            Some(&t) => {
                self.pos += 1;
                Ok(t)
            }
            None => Err(self.error_end(expected)),
        }
    }

    /// The next token and its line, not read (`("", last line)` at the end).
    pub(super) fn peek(&self) -> (&'a str, usize) {
        self.toks
            .get(self.pos)
            .copied()
            .unwrap_or(("", self.last_line))
    }

    /// Skips the tokens left on `line`.
    pub(super) fn skip_line(&mut self, line: usize) {
        while self.toks.get(self.pos).is_some_and(|t| t.1 == line) {
            self.pos += 1;
        }
    }

    /// The next token, which must be `word`.
    pub(super) fn word(&mut self, word: &str, expected: &str) -> Result<(), Fc2dError> {
        let (t, l) = self.next(expected)?;
        if t == word {
            Ok(())
        } else {
            Err(self.error_at(t, l, expected))
        }
    }

    /// A non-negative integer (digits, or an integral `%g` real such as
    /// `1e+06`, below 2⁵³), `trim` characters (a trailing comma) removed.
    pub(super) fn uint_trim(&mut self, trim: &[char], expected: &str) -> Result<usize, Fc2dError> {
        let (t, l) = self.next(expected)?;
        parse_uint(t.trim_end_matches(trim)).ok_or_else(|| self.error_at(t, l, expected))
    }

    /// A non-negative integer.
    pub(super) fn uint(&mut self, expected: &str) -> Result<usize, Fc2dError> {
        self.uint_trim(&[], expected)
    }

    /// A non-negative integer that must be `want`.
    pub(super) fn uint_eq(&mut self, want: usize, expected: &str) -> Result<(), Fc2dError> {
        let (t, l) = self.peek();
        let v = self.uint(expected)?;
        if v == want {
            Ok(())
        } else {
            Err(self.error_at(t, l, expected))
        }
    }

    /// A non-negative integer below `bound`.
    pub(super) fn index(&mut self, bound: usize, expected: &str) -> Result<usize, Fc2dError> {
        let (t, l) = self.peek();
        let v = self.uint(expected)?;
        if v < bound {
            Ok(v)
        } else {
            Err(self.error_at(t, l, expected))
        }
    }

    /// A count of items `per` tokens long each, checked before anything
    /// is allocated for them: at most `(left − reserve) / per`, `reserve`
    /// the tokens that must follow them; `trim` as in [`Self::uint_trim`].
    pub(super) fn count(
        &mut self,
        per: usize,
        reserve: usize,
        trim: &[char],
        expected: &str,
    ) -> Result<usize, Fc2dError> {
        let (t, l) = self.peek();
        let v = self.uint_trim(trim, expected)?;
        let room = self.left().saturating_sub(reserve) / per.max(1);
        if v <= room {
            Ok(v)
        } else {
            Err(self.error_at(
                t,
                l,
                format!(
                    "{expected}; the {} tokens left hold at most {room}",
                    self.left()
                ),
            ))
        }
    }

    /// A finite real (C `%le` or `%g` form).
    pub(super) fn real(&mut self, expected: &str) -> Result<f64, Fc2dError> {
        let (t, l) = self.next(expected)?;
        match t.parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(self.error_at(t, l, expected)),
        }
    }

    /// `n` finite reals (`n` checked against the tokens left by the caller).
    pub(super) fn reals(&mut self, n: usize, what: &str) -> Result<Vec<f64>, Fc2dError> {
        if n > self.left() {
            return Err(self.error_end_count(n, what));
        }
        (0..n)
            .map(|k| self.real(&format!("a finite real ({what}, {} of {n})", k + 1)))
            .collect()
    }

    fn error_end_count(&self, n: usize, what: &str) -> Fc2dError {
        let e = format!("{n} reals ({what}); only {} tokens left", self.left());
        match self.toks.get(self.pos) {
            Some(&(t, l)) => self.error_at(t, l, e),
            None => self.error_end(e),
        }
    }
}

/// A non-negative integer: digits, or an integral real below 2⁵³ (`%g`
/// prints 1000000 as `1e+06`).
pub(super) fn parse_uint(s: &str) -> Option<usize> {
    s.parse::<usize>().ok().or_else(|| {
        s.parse::<f64>()
            .ok()
            .filter(|x| x.is_finite() && *x >= 0.0 && x.fract() == 0.0 && *x < 9.0e15)
            .map(|x| x as usize)
    })
}
