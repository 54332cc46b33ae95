//! Which of the two formats a scenario text is written in ([`FileKind`]): told apart before
//! either loader parses it, so that each can say when it is given the other (this module
//! names neither loader, which both name it).

/// The two formats a scenario file may be written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileKind {
    /// A star world (`crate::Scenario`: `[workspace]`, star `[[obstacles]]`).
    Star,
    /// A floor plan (`crate::floorplan::FloorScenario`: a `[floor_plan]` table).
    FloorPlan,
}

impl FileKind {
    /// The format of scenario text: a floor plan when its top level has a `[floor_plan]`
    /// table, a star world otherwise.
    #[must_use]
    pub fn of_text(text: &str) -> Self {
        match toml::from_str::<toml::Table>(text) {
            Ok(table) if table.contains_key("floor_plan") => Self::FloorPlan,
            Ok(_) => Self::Star,
            // A syntax or value error (`1e400`, 2⁶⁴) fails the table's parse too: the header is
            // found by a scan of the lines, so that the floor-plan loader names the real error
            // instead of the star loader's "unknown field `floor_plan`" (issue 56, D11).
            Err(_) if text.lines().any(names_floor_plan) => Self::FloorPlan,
            Err(_) => Self::Star,
        }
    }
}

/// Whether a line of TOML opens the `[floor_plan]` table (or a sub-table of it) or sets one of
/// its keys at the top level (`floor_plan.map = …`).
fn names_floor_plan(line: &str) -> bool {
    let line = line.trim_start();
    let key = line
        .strip_prefix('[')
        .map_or(line, |rest| rest.trim_start_matches('[').trim_start());
    let key = key
        .strip_prefix('"')
        .and_then(|k| k.strip_prefix("floor_plan\""))
        .or_else(|| key.strip_prefix("floor_plan"));
    key.is_some_and(|rest| {
        let rest = rest.trim_start();
        rest.starts_with(']') || rest.starts_with('.') || rest.starts_with('=')
    })
}
