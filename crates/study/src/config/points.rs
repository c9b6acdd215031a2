//! The points of a sweep: its `[sweep]` table read as the list of studies it stands for.
//! [`points`] writes each value into the study's settings as TOML and reads them back, so each
//! point is checked exactly as a study file would be, and a misspelt key is refused with its
//! name. Running them is [`crate::sweep`]'s business.

use super::StudyConfig;

/// The study of every point of `config`'s sweep, in order (each without the `[sweep]`
/// table and checked); the message names the key and the value's index.
pub fn points(config: &StudyConfig) -> Result<Vec<StudyConfig>, String> {
    let Some(sweep) = &config.sweep else {
        return Ok(vec![config.clone()]);
    };
    if sweep.values.is_empty() {
        return Err("sweep.values is empty: expected at least one value".into());
    }
    for (i, v) in sweep.values.iter().enumerate() {
        if !v.is_finite() {
            return Err(format!("sweep.values[{i}] = {v}: expected a finite number"));
        }
        if sweep.values[..i].contains(v) {
            return Err(format!(
                "sweep.values[{i}] = {v} is listed twice; expected each value once"
            ));
        }
    }
    let path: Vec<&str> = sweep.key.split('.').collect();
    if path.iter().any(|p| p.is_empty()) || path[0] == "sweep" {
        return Err(format!(
            "sweep.key = `{}`: expected the dotted path of a numeric setting, e.g. \
             `truth.initial_tilt.azimuth_rad`",
            sweep.key
        ));
    }
    let mut base = config.clone();
    base.sweep = None;
    let value = toml::Value::try_from(&base).map_err(|e| e.to_string())?;
    sweep
        .values
        .iter()
        .enumerate()
        .map(|(i, &v)| {
            let mut value = value.clone();
            set(&mut value, &path, v).map_err(|e| format!("sweep.key = `{}`: {e}", sweep.key))?;
            let point: StudyConfig = value.try_into().map_err(|e: toml::de::Error| {
                format!(
                    "sweep.values[{i}] = {v} for `{}`: {}",
                    sweep.key,
                    e.message()
                )
            })?;
            point
                .validate()
                .map_err(|e| format!("sweep.values[{i}] = {v} for `{}`: {e}", sweep.key))?;
            Ok(point)
        })
        .collect()
}

/// Writes `v` at `path` in `value`: over a number (an integer setting takes integral values
/// only), or as a new key of an existing table (a setting left at no value, such as a
/// variant's alpha; reading the result back refuses a name the study does not know). A
/// component may index a list, as located errors write it: `trajectory.segment[1].to`,
/// `trajectory.segment[3].segments[0].duration_s`.
fn set(value: &mut toml::Value, path: &[&str], v: f64) -> Result<(), String> {
    let (last, parents) = path.split_last().expect("a non-empty path");
    let mut table = value;
    for (depth, p) in parents.iter().enumerate() {
        let here = || path[..=depth].join(".");
        table = component(table, p, &here)?;
        if !table.is_table() {
            return Err(format!("`{}` is not a table of settings", here()));
        }
    }
    // The last component: a key of `table`, or an element of a list under it.
    let (name, indices) = split_indices(last).map_err(|e| format!("`{last}`: {e}"))?;
    let (container, key): (&mut toml::Value, Slot) = match indices.split_last() {
        None => (table, Slot::Key(name.to_string())),
        Some((&i, outer)) => {
            let mut list = table
                .get_mut(name)
                .ok_or_else(|| format!("no setting `{}` in the study", path.join(".")))?;
            for &j in outer {
                list = element(list, j, &|| path.join("."))?;
            }
            (list, Slot::Index(i))
        }
    };
    let current = match (&*container, &key) {
        (toml::Value::Table(t), Slot::Key(k)) => t.get(k),
        (toml::Value::Array(a), Slot::Index(i)) => Some(a.get(*i).ok_or_else(|| {
            format!(
                "`{}` has {} entries, not {}",
                path.join("."),
                a.len(),
                i + 1
            )
        })?),
        _ => return Err(format!("`{}` is not a list", path.join("."))),
    };
    let new = match current {
        Some(toml::Value::Integer(_)) => {
            if v.fract() != 0.0 || v.abs() > 9.0e15 {
                return Err(format!(
                    "{v} is not a whole number, which this setting takes"
                ));
            }
            toml::Value::Integer(v as i64)
        }
        Some(toml::Value::Float(_)) | None => toml::Value::Float(v),
        Some(other) => {
            return Err(format!(
                "the setting is a {}, not a number",
                other.type_str()
            ))
        }
    };
    match (container, key) {
        (toml::Value::Table(t), Slot::Key(k)) => {
            t.insert(k, new);
        }
        (toml::Value::Array(a), Slot::Index(i)) => a[i] = new,
        _ => unreachable!("matched above"),
    }
    Ok(())
}

/// Where the swept number goes: a table's key or a list's element.
enum Slot {
    Key(String),
    Index(usize),
}

/// `value`'s entry `comp` (`name` or `name[i][j]`); `here` names the path so far.
fn component<'v>(
    value: &'v mut toml::Value,
    comp: &str,
    here: &dyn Fn() -> String,
) -> Result<&'v mut toml::Value, String> {
    let (name, indices) = split_indices(comp).map_err(|e| format!("`{}`: {e}", here()))?;
    let mut v = value
        .get_mut(name)
        .ok_or_else(|| format!("no table `{}` in the study", here()))?;
    for i in indices {
        v = element(v, i, here)?;
    }
    Ok(v)
}

/// Element `i` of the list `value`.
fn element<'v>(
    value: &'v mut toml::Value,
    i: usize,
    here: &dyn Fn() -> String,
) -> Result<&'v mut toml::Value, String> {
    let toml::Value::Array(a) = value else {
        return Err(format!("`{}` is not a list", here()));
    };
    let n = a.len();
    a.get_mut(i)
        .ok_or_else(|| format!("`{}` has {n} entries, not {}", here(), i + 1))
}

/// `name[1][2]` -> (`name`, [1, 2]).
fn split_indices(comp: &str) -> Result<(&str, Vec<usize>), String> {
    let Some(open) = comp.find('[') else {
        return Ok((comp, Vec::new()));
    };
    let (name, mut rest) = comp.split_at(open);
    let mut indices = Vec::new();
    while !rest.is_empty() {
        let inner = rest
            .strip_prefix('[')
            .and_then(|r| r.split_once(']'))
            .ok_or("expected an index in brackets, e.g. `segment[1]`")?;
        indices.push(
            inner
                .0
                .parse::<usize>()
                .map_err(|_| format!("`[{}]`: expected an index 0, 1, 2, ...", inner.0))?,
        );
        rest = inner.1;
    }
    if name.is_empty() {
        return Err("expected a name before the index".into());
    }
    Ok((name, indices))
}
