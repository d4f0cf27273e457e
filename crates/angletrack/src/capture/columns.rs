//! Which columns of a capture hold the time, the two signals and the reference angle: the
//! user's mapping (`y_c=cos,y_s=sin,time=t`), or the usual names, resolved against the
//! header; and the time columns of an oscilloscope's (x, y) column pairs.

use core::fmt;
use core::str::FromStr;

/// What a column of a capture holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Role {
    /// Time stamps (in the capture's time unit).
    Time,
    /// The cosine signal `y_c ~ A cos(theta)`.
    Cosine,
    /// The sine signal `y_s ~ A sin(theta)`.
    Sine,
    /// A reference angle (rad, unwrapped or wrapped), e.g. from an encoder.
    Reference,
    /// A resolver's excitation, sampled with its windings (any offset and amplitude).
    Excitation,
}

impl Role {
    /// Every role, in the order of a [`ResolvedColumns::indices`].
    pub const ALL: [Role; 5] = [
        Role::Time,
        Role::Cosine,
        Role::Sine,
        Role::Reference,
        Role::Excitation,
    ];

    /// The role's key in a column mapping: `time`, `y_c`, `y_s`, `reference`, `excitation`.
    pub const fn key(self) -> &'static str {
        match self {
            Role::Time => "time",
            Role::Cosine => "y_c",
            Role::Sine => "y_s",
            Role::Reference => "reference",
            Role::Excitation => "excitation",
        }
    }

    /// Header names taken for the role when no mapping names its column (compared without
    /// case and surrounding blanks), most specific first.
    const fn usual_names(self) -> &'static [&'static str] {
        match self {
            Role::Time => &["time", "time_s", "t", "x-axis"],
            Role::Cosine => &["y_c", "cos", "cosine", "y_cos"],
            Role::Sine => &["y_s", "sin", "sine", "y_sin"],
            Role::Reference => &["reference", "reference_rad", "theta", "angle", "angle_rad"],
            Role::Excitation => &["excitation", "exc"],
        }
    }
}

impl fmt::Display for Role {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.key())
    }
}

/// The column value that leaves a role out: `time=-` ignores a time column.
pub const NO_COLUMN: &str = "-";

/// A user's choice of columns: for some roles, a header name or a 0-based index.
///
/// A value is the column of that header name if the header has one; otherwise a whole
/// number is a 0-based index (headerless files and `.npy` arrays are mapped by index).
/// [`NO_COLUMN`] (`-`) for the time or the reference ignores the column the usual names
/// would find (`time=-`: the sample rate is then the stated one).
///
/// ```
/// use angletrack::capture::{ColumnMap, Role};
/// let map: ColumnMap = "y_c=cos, y_s=sin, time=-".parse()?;
/// assert_eq!(map.get(Role::Sine), Some("sin"));
/// assert_eq!(map.get(Role::Time), Some("-"));
/// assert!("y_c=cos,y_c=sin".parse::<ColumnMap>().is_err()); // twice
/// assert!("y_c=-".parse::<ColumnMap>().is_err()); // the signals cannot be ignored
/// # Ok::<(), String>(())
/// ```
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ColumnMap {
    entries: Vec<(Role, String)>,
}

impl ColumnMap {
    /// The column named for `role`, if the mapping names one.
    pub fn get(&self, role: Role) -> Option<&str> {
        self.entries
            .iter()
            .find(|(r, _)| *r == role)
            .map(|(_, c)| c.as_str())
    }

    /// Names `column` (a header name or a 0-based index) for `role`; refuses a role named
    /// twice.
    pub fn set(&mut self, role: Role, column: &str) -> Result<(), String> {
        if self.get(role).is_some() {
            return Err(format!("columns: {role} is given twice"));
        }
        let column = column.trim();
        if column.is_empty() {
            return Err(format!("columns: {role} names no column"));
        }
        if column == NO_COLUMN && matches!(role, Role::Cosine | Role::Sine) {
            return Err(format!(
                "columns: {role}=- : the signals cannot be left out (only time and reference)"
            ));
        }
        self.entries.push((role, column.to_string()));
        Ok(())
    }
}

impl FromStr for ColumnMap {
    type Err = String;

    /// Parses `role=column` pairs separated by commas; the roles are `time`, `y_c`, `y_s` and
    /// `reference`.
    fn from_str(text: &str) -> Result<Self, String> {
        let mut map = ColumnMap::default();
        for item in text.split(',').filter(|i| !i.trim().is_empty()) {
            let (key, column) = item.split_once('=').ok_or_else(|| {
                format!("columns: expected ROLE=COLUMN (e.g. y_c=cos), got {item:?}")
            })?;
            let key = key.trim();
            let role = Role::ALL
                .into_iter()
                .find(|r| r.key() == key)
                .ok_or_else(|| {
                    format!("columns: unknown role {key:?}: expected time, y_c, y_s, reference or excitation")
                })?;
            map.set(role, column)?;
        }
        Ok(map)
    }
}

/// The columns a capture is read from, resolved against its header (0-based indices).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ResolvedColumns {
    /// The column of each role in [`Role::ALL`] order (`None`: the capture has none).
    pub indices: [Option<usize>; 5],
    /// The further time columns of the signals (an oscilloscope's (x, y) pairs): each must
    /// agree with the time column row by row.
    pub other_times: Vec<usize>,
    /// Every column's name (the header's, or its index when there is no header).
    pub names: Vec<String>,
}

impl ResolvedColumns {
    /// The column of `role`.
    pub fn index(&self, role: Role) -> Option<usize> {
        let i = Role::ALL.iter().position(|r| *r == role).unwrap_or(0);
        self.indices[i]
    }

    /// The name of column `index` as the file spells it (its index without a header).
    pub fn name(&self, index: usize) -> &str {
        self.names.get(index).map_or("", String::as_str)
    }

    /// The mapping that was used, `time=t,y_c=cos,...`, for messages and metadata.
    pub fn mapping(&self) -> Vec<(Role, String)> {
        Role::ALL
            .into_iter()
            .filter_map(|r| self.index(r).map(|i| (r, self.name(i).to_string())))
            .collect()
    }
}

/// A header name as compared: without case, surrounding blanks or a trailing unit in
/// brackets (`Time (s)` and `time [s]` are `time`).
fn normalised(name: &str) -> String {
    let name = name.trim();
    let bare = match name.rfind(['(', '[']) {
        Some(open) if name.ends_with([')', ']']) && open > 0 => &name[..open],
        _ => name,
    };
    bare.trim().to_ascii_lowercase()
}

/// Whether a header name is an oscilloscope's time (x) column: `t`, `time`, `x-axis`,
/// `second`, or one of those with a channel number (`t1`, `time 2`).
pub fn is_time_name(name: &str) -> bool {
    let n = normalised(name);
    let base = n.trim_end_matches(|c: char| c.is_ascii_digit() || c == ' ' || c == '_');
    matches!(
        base,
        "t" | "time" | "time_s" | "x-axis" | "x" | "second" | "seconds" | "s"
    )
}

/// The column `wanted` names among `names`: a header name (without case), else a 0-based
/// index; `has_header` tells whether the names come from the file.
fn find(names: &[String], wanted: &str, has_header: bool) -> Option<usize> {
    let w = normalised(wanted);
    if has_header && let Some(i) = names.iter().position(|n| normalised(n) == w) {
        return Some(i);
    }
    w.parse::<usize>().ok().filter(|&i| i < names.len())
}

/// Resolves `map` (roles it does not name get their usual names) against the column
/// `names`; the error says which role is missing and what the columns are.
pub fn resolve(
    map: &ColumnMap,
    names: &[String],
    has_header: bool,
) -> Result<ResolvedColumns, String> {
    let listed = || {
        names
            .iter()
            .enumerate()
            .map(|(i, n)| format!("{i}: {n:?}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut indices = [None; 5];
    for (slot, role) in indices.iter_mut().zip(Role::ALL) {
        *slot = match map.get(role) {
            Some(NO_COLUMN) => None,
            Some(wanted) => Some(find(names, wanted, has_header).ok_or_else(|| {
                format!(
                    "columns: {role}={wanted} names no column (the columns are {})",
                    listed()
                )
            })?),
            None if has_header => role.usual_names().iter().find_map(|u| find(names, u, true)),
            None => None,
        };
    }
    for role in [Role::Cosine, Role::Sine] {
        if indices[Role::ALL.iter().position(|r| *r == role).unwrap_or(0)].is_none() {
            let how = if has_header {
                format!(
                    "the header names no {role} column (the columns are {}); name it with \
                     columns, e.g. y_c=cos,y_s=sin",
                    listed()
                )
            } else {
                format!(
                    "the capture has no header line ({} columns): name the signals' columns by \
                     0-based index, e.g. y_c=0,y_s=1",
                    names.len()
                )
            };
            return Err(format!("no y_c and y_s columns: {how}"));
        }
    }
    for (a, role_a) in Role::ALL.into_iter().enumerate() {
        for (b, role_b) in Role::ALL.into_iter().enumerate().skip(a + 1) {
            if let (Some(i), Some(j)) = (indices[a], indices[b])
                && i == j
            {
                return Err(format!(
                    "columns: {role_a} and {role_b} are both column {i} ({:?}): each role needs \
                     its own column",
                    names.get(i).map_or("", String::as_str)
                ));
            }
        }
    }
    // A signal's column found by a name the header gives twice could be either: the first
    // is no more likely than the other (the time column's repeats are an oscilloscope's
    // (x, y) pairs, `pair_times`).
    for (index, role) in indices.iter().zip(Role::ALL) {
        let Some(i) = *index else { continue };
        let wanted = map.get(role);
        let by_index = wanted.is_some_and(|w| {
            w.trim().parse::<usize>() == Ok(i) && normalised(&names[i]) != normalised(w)
        });
        let same: Vec<usize> = (0..names.len())
            .filter(|&j| normalised(&names[j]) == normalised(&names[i]))
            .collect();
        if has_header && role != Role::Time && !by_index && same.len() > 1 {
            let listed: Vec<String> = same.iter().map(usize::to_string).collect();
            return Err(format!(
                "columns: {role}={} is ambiguous: columns {} are all named {:?}; name one by \
                 its 0-based index, e.g. {role}={}",
                wanted.unwrap_or(&names[i]),
                listed.join(" and "),
                names[i],
                same[same.len() - 1]
            ));
        }
    }
    let mut resolved = ResolvedColumns {
        indices,
        other_times: Vec::new(),
        names: names.to_vec(),
    };
    if map.get(Role::Time) != Some(NO_COLUMN) {
        pair_times(&mut resolved, has_header);
    }
    Ok(resolved)
}

/// With (x, y) column pairs (more than one time column in the header), each signal's own time
/// column is the nearest one to its left: the first is the time column unless the mapping
/// named one, and the others must agree with it.
fn pair_times(resolved: &mut ResolvedColumns, has_header: bool) {
    if !has_header || resolved.names.iter().filter(|n| is_time_name(n)).count() < 2 {
        return;
    }
    let own_time = |j: usize| (0..j).rev().find(|&i| is_time_name(&resolved.names[i]));
    let signals = [Role::Cosine, Role::Sine, Role::Reference];
    let mut times: Vec<usize> = signals
        .iter()
        .filter_map(|&r| resolved.index(r).and_then(own_time))
        .collect();
    times.dedup();
    if resolved.indices[0].is_none() {
        resolved.indices[0] = times.first().copied();
    }
    let time = resolved.indices[0];
    let mut others: Vec<usize> = times.into_iter().filter(|&t| Some(t) != time).collect();
    others.sort_unstable();
    others.dedup();
    resolved.other_times = others;
}
