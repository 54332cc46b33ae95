//! The map_server YAML keys, read with yaml-rust2 (a pure-Rust YAML 1.2 parser) and checked one
//! by one, so that every error names its key.

use yaml_rust2::parser::{Event, EventReceiver, Parser};
use yaml_rust2::{Yaml, YamlLoader};

use super::MapMode;
use super::error::MapProblem;

/// Whether the parser met an alias.
struct Aliases(bool);

impl EventReceiver for Aliases {
    fn on_event(&mut self, ev: Event) {
        self.0 |= matches!(ev, Event::Alias(_));
    }
}

/// The YAML keys of a map_server map, validated.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct MapYaml {
    pub image: String,
    pub resolution: f64,
    pub origin: [f64; 3],
    pub negate: bool,
    pub occupied_thresh: f64,
    pub free_thresh: f64,
    pub mode: MapMode,
}

/// A YAML file larger than this is refused before parsing (a map's YAML is a few hundred
/// bytes; this bounds the parser's time and memory on a wrong file).
pub(crate) const MAX_YAML_BYTES: usize = 1 << 20;

/// At most this many characters of a wrong value are quoted in an error.
const QUOTE: usize = 40;

fn quote(y: &Yaml) -> String {
    let s = match y {
        Yaml::Real(s) | Yaml::String(s) => s.clone(),
        Yaml::Integer(i) => i.to_string(),
        Yaml::Boolean(b) => b.to_string(),
        Yaml::Array(a) => format!("a list of {}", a.len()),
        Yaml::Hash(_) => "a mapping".into(),
        Yaml::Null => "null".into(),
        Yaml::Alias(_) => "an alias".into(),
        Yaml::BadValue => "nothing".into(),
    };
    if s.chars().count() > QUOTE {
        s.chars().take(QUOTE).chain("…".chars()).collect()
    } else {
        s
    }
}

fn invalid(field: &'static str, expected: &'static str, y: &Yaml) -> MapProblem {
    MapProblem::InvalidField {
        field,
        expected,
        found: quote(y),
    }
}

/// A number: YAML reals and integers (`resolution: 1`, `origin: [-10, -10, 0]` are common),
/// and a quoted one (`resolution: "0.05"`), which map_server's yaml-cpp reads as the number
/// (issue 56, D19.6).
fn number(y: &Yaml) -> Option<f64> {
    match y {
        Yaml::Real(_) => y.as_f64(),
        #[allow(clippy::cast_precision_loss)] // map coordinates are far below 2^53
        Yaml::Integer(i) => Some(*i as f64),
        // A decimal number only (YAML's own `0x10`, `0o7` and `.inf` forms are not what
        // yaml-cpp's `as<double>` reads in a string).
        Yaml::String(s) => s.trim().parse::<f64>().ok().filter(|_| {
            s.trim()
                .bytes()
                .all(|b| b.is_ascii_digit() || b"+-.eE".contains(&b))
        }),
        _ => None,
    }
}

/// The resolutions a map may have, m/pixel: a micron to a kilometre per pixel. Outside, the
/// pixel geometry is below what the outline's arithmetic resolves (issue 56, D19.7: at
/// `1e-300` the outline lost the goal's pixel) or coarser than any robot.
pub const RESOLUTION_RANGE: (f64, f64) = (1e-6, 1e3);

fn get<'a>(doc: &'a Yaml, field: &'static str) -> Result<&'a Yaml, MapProblem> {
    match &doc[field] {
        Yaml::BadValue => Err(MapProblem::MissingField { field }),
        y => Ok(y),
    }
}

fn finite(field: &'static str, y: &Yaml) -> Result<f64, MapProblem> {
    number(y)
        .filter(|v| v.is_finite())
        .ok_or_else(|| invalid(field, "a finite number", y))
}

fn threshold(doc: &Yaml, field: &'static str) -> Result<f64, MapProblem> {
    let y = get(doc, field)?;
    let v = number(y).ok_or_else(|| invalid(field, "a number in [0, 1]", y))?;
    if !(0.0..=1.0).contains(&v) {
        return Err(MapProblem::Threshold { field, value: v });
    }
    Ok(v)
}

/// Parses and checks the keys: `image` (a non-empty string), `resolution` (in
/// [`RESOLUTION_RANGE`]),
/// `origin` (`[x, y, yaw]`, finite), `negate` (`0`/`1` as map_server writes it, or a boolean),
/// `occupied_thresh` and `free_thresh` (in `[0, 1]`, `free < occupied`), optional `mode`
/// (`trinary`, the default, `scale` or `raw`). Other keys are ignored, as map_server does.
pub(crate) fn parse(text: &str) -> Result<MapYaml, MapProblem> {
    // YAML allows a byte-order mark; it is not part of the first key (issue 56, D19.5).
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if text.len() > MAX_YAML_BYTES {
        return Err(MapProblem::Yaml(format!(
            "{} bytes; a map's YAML has at most {MAX_YAML_BYTES}",
            text.len()
        )));
    }
    // Guard: the loader expands every alias in place, so nested aliases ("billion laughs")
    // of a few hundred bytes grow without bound. A map_server YAML has none: they are
    // refused from the parser's events, before anything is built.
    let mut aliases = Aliases(false);
    Parser::new_from_str(text)
        .load(&mut aliases, true)
        .map_err(|e| MapProblem::Yaml(e.to_string()))?;
    if aliases.0 {
        return Err(MapProblem::Yaml(
            "anchors and aliases (`*name`) are not supported in a map's YAML".into(),
        ));
    }
    let docs = YamlLoader::load_from_str(text).map_err(|e| MapProblem::Yaml(e.to_string()))?;
    let doc = match docs.first() {
        Some(d @ Yaml::Hash(_)) => d,
        Some(_) => {
            return Err(MapProblem::Yaml(
                "the document is not a mapping of keys".into(),
            ));
        }
        None => return Err(MapProblem::Yaml("the file is empty".into())),
    };
    let image = match get(doc, "image")? {
        Yaml::String(s) if !s.trim().is_empty() => s.clone(),
        y => return Err(invalid("image", "the image file's path (a string)", y)),
    };
    let resolution = {
        let y = get(doc, "resolution")?;
        let r = number(y).ok_or_else(|| invalid("resolution", "a number (m/pixel)", y))?;
        let (lo, hi) = RESOLUTION_RANGE;
        if !(r.is_finite() && (lo..=hi).contains(&r)) {
            return Err(MapProblem::Resolution(r));
        }
        r
    };
    let origin = match get(doc, "origin")? {
        Yaml::Array(a) if a.len() == 3 => [
            finite("origin", &a[0])?,
            finite("origin", &a[1])?,
            finite("origin", &a[2])?,
        ],
        y => return Err(invalid("origin", "a list [x, y, yaw]", y)),
    };
    let negate = match get(doc, "negate")? {
        Yaml::Integer(0) | Yaml::Boolean(false) => false,
        Yaml::Integer(1) | Yaml::Boolean(true) => true,
        Yaml::String(s) if s.trim() == "0" => false,
        Yaml::String(s) if s.trim() == "1" => true,
        y => return Err(invalid("negate", "0 or 1 (or false / true)", y)),
    };
    let occupied_thresh = threshold(doc, "occupied_thresh")?;
    let free_thresh = threshold(doc, "free_thresh")?;
    if free_thresh >= occupied_thresh {
        return Err(MapProblem::ThresholdOrder {
            free: free_thresh,
            occupied: occupied_thresh,
        });
    }
    let mode = match &doc["mode"] {
        Yaml::BadValue => MapMode::Trinary,
        Yaml::String(s) => match s.as_str() {
            "trinary" => MapMode::Trinary,
            "scale" => MapMode::Scale,
            "raw" => MapMode::Raw,
            _ => return Err(invalid("mode", "trinary, scale or raw", &doc["mode"])),
        },
        y => return Err(invalid("mode", "trinary, scale or raw", y)),
    };
    Ok(MapYaml {
        image,
        resolution,
        origin,
        negate,
        occupied_thresh,
        free_thresh,
        mode,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = "image: m.pgm\nresolution: 0.05\norigin: [-1.0, 2, 0.0]\nnegate: 0\n\
                        occupied_thresh: 0.65\nfree_thresh: 0.196\n";

    #[test]
    fn reads_the_keys_with_integers_and_defaults() {
        let m = parse(GOOD).unwrap();
        assert_eq!(m.image, "m.pgm");
        assert_eq!(m.origin, [-1.0, 2.0, 0.0]);
        assert_eq!((m.negate, m.mode), (false, MapMode::Trinary));
        let m = parse(&format!("{GOOD}mode: raw\n")).unwrap();
        assert_eq!(m.mode, MapMode::Raw);
        let m = parse(&GOOD.replace("negate: 0", "negate: true")).unwrap();
        assert!(m.negate);
    }

    /// Nested aliases ("billion laughs": nine levels of ten, 10⁹ scalars once expanded, in
    /// 300 bytes) are refused before the loader expands them; a plain anchor with its alias
    /// too, as a map has no use for them.
    #[test]
    fn aliases_are_refused_before_they_are_expanded() {
        let mut laughs = String::from("a: &a [x,x,x,x,x,x,x,x,x,x]\n");
        for (prev, name) in "abcdefgh".chars().zip("bcdefghi".chars()) {
            let refs = vec![format!("*{prev}"); 10].join(",");
            laughs.push_str(&format!("{name}: &{name} [{refs}]\n"));
        }
        for text in [format!("{laughs}{GOOD}"), format!("{GOOD}x: &r 1\ny: *r\n")] {
            let e = parse(&text).unwrap_err();
            assert!(e.to_string().contains("aliases"), "{e}");
        }
        // An anchor alone is harmless and allowed.
        assert!(parse(&format!("{GOOD}x: &r 1\n")).is_ok());
    }

    /// A byte-order mark before the first key is YAML's, not the key's (it read "the key
    /// `image` is missing").
    #[test]
    fn a_byte_order_mark_is_not_part_of_the_first_key() {
        let m = parse(&format!("\u{feff}{GOOD}")).unwrap();
        assert_eq!(m, parse(GOOD).unwrap());
    }

    /// Each wrong file names its key.
    #[test]
    fn every_error_names_the_key() {
        let check = |text: String, field: &str| {
            let e = parse(&text).unwrap_err();
            assert!(e.to_string().contains(field), "{e} should name {field}");
        };
        for key in [
            "image",
            "resolution",
            "origin",
            "negate",
            "occupied_thresh",
            "free_thresh",
        ] {
            let text: String = GOOD
                .lines()
                .filter(|l| !l.starts_with(&format!("{key}:")))
                .map(|l| format!("{l}\n"))
                .collect();
            check(text, key);
        }
        check(GOOD.replace("0.05", "-0.05"), "resolution");
        check(GOOD.replace("0.05", "0"), "resolution");
        check(GOOD.replace("0.05", ".nan"), "resolution");
        check(GOOD.replace("0.05", "fine"), "resolution");
        check(GOOD.replace("0.05", "1e-300"), "resolution");
        check(GOOD.replace("0.05", "\"1e-300\""), "resolution");
        check(GOOD.replace("0.05", "2e3"), "resolution");
        check(GOOD.replace("[-1.0, 2, 0.0]", "[1, 2]"), "origin");
        check(GOOD.replace("[-1.0, 2, 0.0]", "[1, .inf, 0]"), "origin");
        check(GOOD.replace("negate: 0", "negate: 2"), "negate");
        check(GOOD.replace("0.65", "1.5"), "occupied_thresh");
        check(GOOD.replace("0.196", "-0.1"), "free_thresh");
        check(GOOD.replace("0.196", "0.7"), "free_thresh");
        check(format!("{GOOD}mode: fancy\n"), "mode");
        check(GOOD.replace("m.pgm", "''"), "image");
    }

    /// Quoted numbers are numbers, as map_server's yaml-cpp reads them (issue 56, D19.6); a
    /// quoted word is still refused by name.
    #[test]
    fn quoted_numbers_are_numbers() {
        let plain = parse(GOOD).unwrap();
        let quoted = GOOD
            .replace("0.05", "\"0.05\"")
            .replace("[-1.0, 2, 0.0]", "['-1.0', \"2\", 0.0]")
            .replace("negate: 0", "negate: \"0\"")
            .replace("0.65", "' 0.65'")
            .replace("0.196", "\"0.196\"");
        let q = parse(&quoted).unwrap();
        assert_eq!(
            (
                q.resolution,
                q.origin,
                q.negate,
                q.occupied_thresh,
                q.free_thresh
            ),
            (
                plain.resolution,
                plain.origin,
                plain.negate,
                plain.occupied_thresh,
                plain.free_thresh
            )
        );
        assert!(
            parse(&GOOD.replace("negate: 0", "negate: \"1\""))
                .unwrap()
                .negate
        );
        let e = parse(&GOOD.replace("0.05", "\"fine\"")).unwrap_err();
        assert!(e.to_string().contains("resolution"), "{e}");
        for bad in ["\"2\"", "\"1.0\""] {
            let e = parse(&GOOD.replace("negate: 0", &format!("negate: {bad}"))).unwrap_err();
            assert!(e.to_string().contains("negate"), "{e}");
        }
        // YAML's other number forms are not decimal numbers in a string.
        for bad in ["\"0x10\"", "\"0o7\"", "\".inf\"", "\"\""] {
            let e = parse(&GOOD.replace("0.05", bad)).unwrap_err();
            assert!(e.to_string().contains("resolution"), "{bad}: {e}");
        }
    }

    #[test]
    fn not_a_mapping_or_not_yaml() {
        assert!(matches!(parse(""), Err(MapProblem::Yaml(_))));
        assert!(matches!(parse("- 1\n- 2\n"), Err(MapProblem::Yaml(_))));
        assert!(matches!(parse("image: [a\n"), Err(MapProblem::Yaml(_))));
    }
}
