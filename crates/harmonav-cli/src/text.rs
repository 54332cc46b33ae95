//! What the CLI writes to the terminal: lines of text with every control character escaped
//! (a name holding an ESC sequence could otherwise retitle or clear the terminal), and JSON
//! (escaped by serde). Both end the program quietly when stdout is closed.

use std::borrow::Cow;
use std::io::Write as _;

/// Bidirectional-formatting characters (embeddings, overrides, isolates): text after them
/// can be shown in another order than it is (CVE-2021-42574, "Trojan Source").
fn reorders(c: char) -> bool {
    matches!(c, '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
}

/// `s` with every control character (C0, DEL, C1: `char::is_control`) and bidirectional
/// formatting character written as a Rust escape (`\u{1b}`, `\n`, `\t`), so that it shows as
/// text and cannot act on the terminal; other text (`Θ`, accents) is unchanged.
pub fn escape(s: &str) -> Cow<'_, str> {
    if !s.chars().any(|c| c.is_control() || reorders(c)) {
        return Cow::Borrowed(s);
    }
    let mut out = String::with_capacity(s.len() + 8);
    for c in s.chars() {
        if c.is_control() || reorders(c) {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// [`escape`] for text of several lines (clap's messages): each line escaped, the line breaks
/// kept.
pub fn escape_lines(s: &str) -> String {
    s.split('\n').map(escape).collect::<Vec<_>>().join("\n")
}

/// Writes `text` and a newline to stdout as it is; a closed stdout (piped into `head`) ends
/// the program with 0, another write error with 2.
pub fn emit(text: &str) {
    if let Err(e) = writeln!(std::io::stdout().lock(), "{text}") {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("harmonav: cannot write the output: {e}");
        std::process::exit(2);
    }
}

/// `println!` for the text output: the line escaped ([`escape`]) and written by [`emit`].
macro_rules! out {
    ($($arg:tt)*) => {
        $crate::text::emit(&$crate::text::escape(&format!($($arg)*)))
    };
}
pub(crate) use out;

/// Prints a value as pretty JSON (the `--json` output of every command; serde escapes the
/// control characters in its strings).
pub fn print_json(value: &impl serde::Serialize) -> Result<(), serde_json::Error> {
    emit(&serde_json::to_string_pretty(value)?);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_are_escaped_and_other_text_is_kept() {
        let check = |input: &str, expected: &str| assert_eq!(escape(input), expected);
        check("rock Θ é", "rock Θ é");
        check(
            "a\u{1b}]0;pwned\u{7}\u{1b}[2J",
            "a\\u{1b}]0;pwned\\u{7}\\u{1b}[2J",
        );
        check("two\nlines\ttab\r", "two\\nlines\\ttab\\r");
        check("del\u{7f} csi\u{9b}", "del\\u{7f} csi\\u{9b}");
        check("abc\u{202e}fed", "abc\\u{202e}fed");
        assert_eq!(escape_lines("a\u{1b}\nb"), "a\\u{1b}\nb");
    }
}
