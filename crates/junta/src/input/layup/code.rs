//! The compact lay-up code: `[0/90/±45]s` to the ply angles, bottom to top.
//!
//! ## Grammar
//!
//! ```text
//! code   := '[' list ']' suffix
//! list   := item ('/' item)*            (',' also separates)
//! item   := (angle | '(' list ')') count?
//! angle  := sign? number                sign: '+' '-' '±' '+-' '∓' '-+'
//! count  := '_'? digits | subscript digits
//! suffix := ( '_'? digits )? ( 's' | 'S' | 'T' )?
//! ```
//!
//! * Plies are listed from the **bottom** of the laminate (the lowest `z`,
//!   the first ply) to the top.
//! * `±45` is the pair `45/-45`, `∓45` the pair `-45/45`; a count repeats
//!   the whole item, so `±45_2` is `45/-45/45/-45` and `(0/90)_2` is
//!   `0/90/0/90`.
//! * The suffix repeats the list `n` times (`[0/90]2` = `0/90/0/90`), then
//!   `s` mirrors it about the mid-plane (`[0/90]s` = `0/90/90/0`,
//!   `[0/90]2s` = `0/90/0/90/90/0/90/0`); `T` (total) changes nothing.
//! * Whitespace is ignored. An odd symmetric lay-up (a mid-plane ply that is
//!   not doubled) is written out in full.

/// The angles (degrees) of the plies of a lay-up code, bottom to top.
///
/// Errors name the position in the code and what was expected.
pub fn parse_layup(code: &str) -> Result<Vec<f64>, String> {
    let chars: Vec<char> = code.chars().filter(|c| !c.is_whitespace()).collect();
    let mut p = Parser { chars, at: 0 };
    p.expect('[')?;
    let list = p.list()?;
    p.expect(']')?;
    let repeat = p.count()?.unwrap_or(1);
    let mut plies: Vec<f64> = (0..repeat).flat_map(|_| list.iter().copied()).collect();
    match p.peek() {
        Some('s' | 'S') => {
            p.at += 1;
            let mirror: Vec<f64> = plies.iter().rev().copied().collect();
            plies.extend(mirror);
        }
        Some('T') => p.at += 1,
        _ => {}
    }
    if let Some(c) = p.peek() {
        return Err(p.error(&format!(
            "unexpected `{c}` after the closing `]`; a code ends with a count, `s` or `T`"
        )));
    }
    Ok(plies)
}

struct Parser {
    chars: Vec<char>,
    at: usize,
}

/// Largest count accepted for one item (a typo guard: `0_1000000`).
const MAX_COUNT: usize = 1000;

impl Parser {
    fn peek(&self) -> Option<char> {
        self.chars.get(self.at).copied()
    }

    fn error(&self, what: &str) -> String {
        let seen: String = self.chars[..self.at.min(self.chars.len())].iter().collect();
        format!("{what} (after `{seen}`)")
    }

    fn expect(&mut self, c: char) -> Result<(), String> {
        if self.peek() == Some(c) {
            self.at += 1;
            Ok(())
        } else {
            let found = self
                .peek()
                .map_or("the end".to_string(), |f| format!("`{f}`"));
            Err(self.error(&format!("expected `{c}`, found {found}")))
        }
    }

    fn list(&mut self) -> Result<Vec<f64>, String> {
        let mut out = self.item()?;
        while matches!(self.peek(), Some('/' | ',')) {
            self.at += 1;
            out.extend(self.item()?);
        }
        Ok(out)
    }

    fn item(&mut self) -> Result<Vec<f64>, String> {
        let one = if self.peek() == Some('(') {
            self.at += 1;
            let l = self.list()?;
            self.expect(')')?;
            l
        } else {
            self.angle()?
        };
        let n = self.count()?.unwrap_or(1);
        Ok((0..n).flat_map(|_| one.iter().copied()).collect())
    }

    /// One angle, or the pair of a `±` / `∓` angle.
    fn angle(&mut self) -> Result<Vec<f64>, String> {
        let rest: String = self.chars[self.at..].iter().take(2).collect();
        let signs: &[f64] = if rest.starts_with('±') {
            self.at += 1;
            &[1.0, -1.0]
        } else if rest.starts_with('∓') {
            self.at += 1;
            &[-1.0, 1.0]
        } else if rest == "+-" {
            self.at += 2;
            &[1.0, -1.0]
        } else if rest == "-+" {
            self.at += 2;
            &[-1.0, 1.0]
        } else if rest.starts_with('-') {
            self.at += 1;
            &[-1.0]
        } else if rest.starts_with('+') {
            self.at += 1;
            &[1.0]
        } else {
            &[1.0]
        };
        let start = self.at;
        while matches!(self.peek(), Some('0'..='9' | '.')) {
            self.at += 1;
        }
        let text: String = self.chars[start..self.at].iter().collect();
        let value: f64 = text
            .parse()
            .map_err(|_| self.error("expected a ply angle in degrees (e.g. 0, 90, ±45, -30.5)"))?;
        Ok(signs.iter().map(|s| s * value).collect())
    }

    /// `_n`, `n` or subscript digits; `None` if there is none.
    fn count(&mut self) -> Result<Option<usize>, String> {
        let underscore = self.peek() == Some('_');
        if underscore {
            self.at += 1;
        }
        let mut n: Option<usize> = None;
        while let Some(d) = self.peek().and_then(digit) {
            n = Some(n.unwrap_or(0).saturating_mul(10).saturating_add(d));
            self.at += 1;
        }
        match n {
            None if underscore => Err(self.error("expected a count after `_`")),
            Some(0) => Err(self.error("a count must be at least 1")),
            Some(k) if k > MAX_COUNT => Err(self.error(&format!(
                "a count of {k} is more than {MAX_COUNT} plies of one item"
            ))),
            n => Ok(n),
        }
    }
}

/// The value of an ASCII or subscript digit.
fn digit(c: char) -> Option<usize> {
    match c {
        '0'..='9' => Some(c as usize - '0' as usize),
        '₀'..='₉' => Some(c as usize - '₀' as usize),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::parse_layup;

    fn p(code: &str) -> Vec<f64> {
        parse_layup(code).unwrap_or_else(|e| panic!("{code}: {e}"))
    }

    #[test]
    fn quasi_isotropic_and_its_relatives() {
        assert_eq!(p("[0/90/±45]s"), [0., 90., 45., -45., -45., 45., 90., 0.]);
        assert_eq!(p("[0/90]"), [0., 90.]);
        assert_eq!(p("[0/90]T"), [0., 90.]);
        assert_eq!(p("[0/90]2s"), [0., 90., 0., 90., 90., 0., 90., 0.]);
        assert_eq!(p("[0/90]_2"), [0., 90., 0., 90.]);
        assert_eq!(p("[ +-30 / 90 ]s"), [30., -30., 90., 90., -30., 30.]);
        assert_eq!(p("[∓45]"), [-45., 45.]);
        assert_eq!(p("[±45_2]"), [45., -45., 45., -45.]);
        assert_eq!(p("[45_2/90₂/-45_2/0_2]s").len(), 16);
        assert_eq!(p("[(0/90)_2/45]"), [0., 90., 0., 90., 45.]);
        assert_eq!(p("[0,22.5,-67.5]"), [0., 22.5, -67.5]);
    }

    #[test]
    fn errors_say_where() {
        for (code, says) in [
            ("0/90", "expected `[`"),
            ("[0/90", "expected `]`"),
            ("[0//90]", "ply angle"),
            ("[0/90]x", "unexpected `x`"),
            ("[0_]", "count after `_`"),
            ("[0_0]", "at least 1"),
            ("[0_5000]", "more than"),
        ] {
            let e = parse_layup(code).unwrap_err();
            assert!(e.contains(says), "{code}: {e}");
        }
    }
}
