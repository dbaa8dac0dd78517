//! Reading scenario files: TOML parsing with precise errors, `include`s, merging, target
//! selection and resolution into a [`Scenario`].

use crate::error::{ScenarioError, from_toml, line_column, one_line};
use crate::flight::Ctx;
use crate::model::{
    Aircraft, AircraftType, DEFAULT_ARRAY_HEIGHT_M, DEFAULT_DURATION_S, Formation, Scenario, Ship, Target,
};
use crate::text_file::{MAX_TEXT_FILE_BYTES, read_text_file};
use crate::validate::{
    fix_references, prune_formation, validate_aircraft, validate_duration, validate_fidelity, validate_formation,
    validate_ship, validate_type,
};
use mimo_core::ids::RadarId;
use mimo_core::params::{Fidelity, RadarParams};
use serde::Deserialize;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::{Path, PathBuf};
use toml::Spanned;

/// Prefix of an include that names a built-in file (`builtin:fighters.toml`).
pub const BUILTIN_PREFIX: &str = "builtin:";

/// The standard scenario files, embedded so the binary works from any directory.
pub(crate) const BUILTIN: &[(&str, &str)] = &[
    ("ships.toml", include_str!("../../../scenarios/ships.toml")),
    ("fighters.toml", include_str!("../../../scenarios/fighters.toml")),
    ("airliners.toml", include_str!("../../../scenarios/airliners.toml")),
    ("1.toml", include_str!("../../../scenarios/1.toml")),
    ("2.toml", include_str!("../../../scenarios/2.toml")),
    ("3.toml", include_str!("../../../scenarios/3.toml")),
    ("4.toml", include_str!("../../../scenarios/4.toml")),
    ("5.toml", include_str!("../../../scenarios/5.toml")),
    ("6.toml", include_str!("../../../scenarios/6.toml")),
    ("7.toml", include_str!("../../../scenarios/7.toml")),
];

fn builtin(name: &str) -> Option<&'static str> {
    BUILTIN.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

/// One scenario file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    name: Option<String>,
    description: Option<String>,
    duration_s: Option<f64>,
    #[serde(default)]
    include: Vec<String>,
    targets: Option<Vec<String>>,
    fidelity: Option<Fidelity>,
    /// Radar parameters shared by every ship; each ship's `radar` table overrides fields.
    radar: Option<Spanned<toml::Table>>,
    #[serde(default)]
    ships: Vec<RawShip>,
    #[serde(default)]
    aircraft_types: BTreeMap<String, AircraftType>,
    #[serde(default)]
    formations: Vec<Formation>,
    #[serde(default)]
    aircraft: Vec<Aircraft>,
    /// Registration biases (docs/model.md §5.5).
    biases: Option<crate::biases::Biases>,
    /// Links between the ships and the test article (docs/model.md §5.6).
    links: Option<crate::links::Links>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawShip {
    id: String,
    lat_deg: f64,
    lon_deg: f64,
    #[serde(default = "default_height")]
    array_height_m: f64,
    heading_deg: f64,
    #[serde(default)]
    speed_mps: f64,
    radar: Option<Spanned<toml::Table>>,
}

fn default_height() -> f64 {
    DEFAULT_ARRAY_HEIGHT_M
}

/// A definition and where it came from (file, index in that file's list).
#[derive(Debug)]
struct From<T> {
    item: T,
    file: String,
    index: usize,
}

/// Everything a file and its includes define.
#[derive(Debug, Default)]
struct Collected {
    name: Option<String>,
    description: Option<String>,
    duration_s: Option<(f64, String)>,
    targets: Option<(Vec<String>, String)>,
    fidelity: Option<(Fidelity, String)>,
    radar: Option<(Spanned<toml::Table>, String)>,
    ships: Vec<From<RawShip>>,
    types: BTreeMap<String, (AircraftType, String)>,
    formations: Vec<From<Formation>>,
    aircraft: Vec<From<Aircraft>>,
    biases: Option<(crate::biases::Biases, String)>,
    links: Option<(crate::links::Links, String)>,
}

impl Collected {
    /// Add the definitions of `other` (an include, or the file itself after its includes).
    /// Settings (name, duration, targets, fidelity, fleet radar) of `other` override;
    /// definitions (ships, aircraft types, formations, aircraft) must not repeat.
    fn merge(&mut self, other: Collected) -> Result<(), ScenarioError> {
        if other.name.is_some() {
            self.name = other.name;
        }
        if other.description.is_some() {
            self.description = other.description;
        }
        if other.duration_s.is_some() {
            self.duration_s = other.duration_s;
        }
        if other.targets.is_some() {
            self.targets = other.targets;
        }
        if other.fidelity.is_some() {
            self.fidelity = other.fidelity;
        }
        if other.radar.is_some() {
            self.radar = other.radar;
        }
        if other.biases.is_some() {
            self.biases = other.biases;
        }
        if other.links.is_some() {
            self.links = other.links;
        }
        for s in other.ships {
            if let Some(prev) = self.ships.iter().find(|p| p.item.id == s.item.id) {
                return Err(ScenarioError::invalid(
                    &s.file,
                    format!("ships[{}].id", s.index),
                    format!("a ship id not defined before, `{}` is also defined in {}", s.item.id, prev.file),
                ));
            }
            self.ships.push(s);
        }
        for (name, (t, file)) in other.types {
            if let Some((_, prev)) = self.types.get(&name) {
                return Err(ScenarioError::invalid(
                    &file,
                    format!("aircraft_types.{name}"),
                    format!("a type name not defined before, `{name}` is also defined in {prev}"),
                ));
            }
            self.types.insert(name, (t, file));
        }
        for f in other.formations {
            if let Some(prev) = self.formations.iter().find(|p| p.item.name == f.item.name) {
                return Err(ScenarioError::invalid(
                    &f.file,
                    format!("formations[{}].name", f.index),
                    format!("a formation name not used before, `{}` is also defined in {}", f.item.name, prev.file),
                ));
            }
            self.formations.push(f);
        }
        self.aircraft.extend(other.aircraft);
        Ok(())
    }
}

/// Where a file's relative includes are looked up.
#[derive(Debug, Clone)]
enum Base {
    Builtin,
    Dir(PathBuf),
    /// Text given without a directory: only `builtin:` includes work.
    Nowhere,
}

#[derive(Default)]
struct Loader {
    /// File texts by display name, for line numbers of late errors.
    texts: HashMap<String, String>,
    /// Files already read (by key), so a file included twice is read once.
    done: HashSet<String>,
    /// The include chain being read, to catch cycles.
    stack: Vec<String>,
}

impl Loader {
    fn file(&mut self, key: String, display: String, text: String, base: Base) -> Result<Collected, ScenarioError> {
        if let Err(e) = text.parse::<toml::Table>() {
            return Err(from_toml(&display, &text, &e, true));
        }
        let raw: RawFile = toml::from_str(&text).map_err(|e| from_toml(&display, &text, &e, false))?;
        self.texts.insert(display.clone(), text);
        self.done.insert(key.clone());
        self.stack.push(key);
        let mut acc = Collected::default();
        for inc in &raw.include {
            let (k, d, t, b) = self.resolve(&display, &base, inc)?;
            if self.stack.contains(&k) {
                return Err(ScenarioError::Include {
                    file: display,
                    include: inc.clone(),
                    reason: "include cycle (the file includes itself, directly or indirectly)".into(),
                });
            }
            if self.done.contains(&k) {
                continue;
            }
            let sub = self.file(k, d, t, b)?;
            acc.merge(sub)?;
        }
        self.stack.pop();
        let own = Collected {
            name: raw.name,
            description: raw.description,
            duration_s: raw.duration_s.map(|d| (d, display.clone())),
            targets: raw.targets.map(|t| (t, display.clone())),
            fidelity: raw.fidelity.map(|f| (f, display.clone())),
            radar: raw.radar.map(|r| (r, display.clone())),
            ships: tag(raw.ships, &display),
            types: raw.aircraft_types.into_iter().map(|(k, v)| (k, (v, display.clone()))).collect(),
            formations: tag(raw.formations, &display),
            aircraft: tag(raw.aircraft, &display),
            biases: raw.biases.map(|b| (b, display.clone())),
            links: raw.links.map(|l| (l, display.clone())),
        };
        acc.merge(own)?;
        Ok(acc)
    }

    /// Find an included file: (key, display name, text, base for its own includes).
    fn resolve(&self, from: &str, base: &Base, inc: &str) -> Result<(String, String, String, Base), ScenarioError> {
        let builtin_name = match (inc.strip_prefix(BUILTIN_PREFIX), base) {
            (Some(name), _) => Some(name),
            (None, Base::Builtin) => Some(inc),
            (None, Base::Dir(_) | Base::Nowhere) => None,
        };
        if let Some(name) = builtin_name {
            let Some(text) = builtin(name) else {
                let names: Vec<&str> = BUILTIN.iter().map(|(n, _)| *n).collect();
                return Err(ScenarioError::Include {
                    file: from.to_string(),
                    include: inc.to_string(),
                    reason: format!("no such built-in file (there are: {})", names.join(", ")),
                });
            };
            let display = format!("{BUILTIN_PREFIX}{name}");
            return Ok((display.clone(), display, text.to_string(), Base::Builtin));
        }
        let dir = match base {
            Base::Dir(d) => d.clone(),
            Base::Builtin => PathBuf::new(),
            Base::Nowhere => {
                return Err(ScenarioError::Include {
                    file: from.to_string(),
                    include: inc.to_string(),
                    reason: format!(
                        "this scenario text has no directory to look in; name a built-in file \
                         as `{BUILTIN_PREFIX}NAME` or load the scenario from a file"
                    ),
                });
            }
        };
        let path = dir.join(inc);
        let display = path.display().to_string();
        let text = read_text_file(&path, MAX_TEXT_FILE_BYTES)
            .map_err(|e| ScenarioError::Io { file: display.clone(), message: format!("{e} (included from {from})") })?;
        let key = std::fs::canonicalize(&path).unwrap_or(path.clone()).display().to_string();
        let parent = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Ok((key, display, text, Base::Dir(parent)))
    }

    /// Line and column of a span in a file read earlier.
    fn place(&self, file: &str, span: std::ops::Range<usize>) -> (usize, usize) {
        self.texts.get(file).map_or((1, 1), |t| line_column(t, span.start))
    }
}

fn tag<T>(items: Vec<T>, file: &str) -> Vec<From<T>> {
    items.into_iter().enumerate().map(|(index, item)| From { item, file: file.to_string(), index }).collect()
}

/// Load the built-in file `name` (e.g. `7.toml`).
pub(crate) fn load_builtin(name: &str, default_name: &str) -> Result<Scenario, ScenarioError> {
    let display = format!("{BUILTIN_PREFIX}{name}");
    let Some(text) = builtin(name) else {
        return Err(ScenarioError::Io { file: display, message: "no such built-in file".into() });
    };
    load_text(text.to_string(), display.clone(), display, Base::Builtin, default_name)
}

/// Load a scenario file from disk.
pub(crate) fn load_file(path: &Path) -> Result<Scenario, ScenarioError> {
    let display = path.display().to_string();
    let text = read_text_file(path, MAX_TEXT_FILE_BYTES)
        .map_err(|e| ScenarioError::Io { file: display.clone(), message: e.to_string() })?;
    let key = std::fs::canonicalize(path).unwrap_or(path.to_path_buf()).display().to_string();
    let base = Base::Dir(path.parent().map(Path::to_path_buf).unwrap_or_default());
    let stem = path.file_stem().map_or("scenario".into(), |s| s.to_string_lossy().into_owned());
    load_text(text, key, display, base, &stem)
}

/// Load a scenario from text, as if read from a file called `name` in `include_dir` (relative
/// includes are looked up there; without a directory only `builtin:` includes work).
pub(crate) fn load_string(text: &str, name: &str, include_dir: Option<&Path>) -> Result<Scenario, ScenarioError> {
    let base = include_dir.map_or(Base::Nowhere, |d| Base::Dir(d.to_path_buf()));
    let stem = Path::new(name).file_stem().map_or("scenario".into(), |s| s.to_string_lossy().into_owned());
    load_text(text.to_string(), format!("<text>{name}"), name.to_string(), base, &stem)
}

fn load_text(
    text: String,
    key: String,
    display: String,
    base: Base,
    default_name: &str,
) -> Result<Scenario, ScenarioError> {
    let mut loader = Loader::default();
    let acc = loader.file(key, display.clone(), text, base)?;
    resolve(&loader, acc, &display, default_name)
}

/// Merge a shared radar table with a ship's overrides and read the parameters.
fn radar_params(
    loader: &Loader,
    fleet: Option<&(Spanned<toml::Table>, String)>,
    own: Option<&Spanned<toml::Table>>,
    file: &str,
    path: &str,
) -> Result<RadarParams, ScenarioError> {
    let mut merged = toml::Table::new();
    if let Some((t, fleet_file)) = fleet {
        parse_radar(loader, t, fleet_file, "radar")?;
        merged.extend(t.get_ref().clone());
    }
    if let Some(t) = own {
        parse_radar(loader, t, file, &format!("{path}.radar"))?;
        merged.extend(t.get_ref().clone());
    }
    let (line, column) = own.map_or((1, 1), |t| loader.place(file, t.span()));
    toml::Value::Table(merged).try_into().map_err(|e| ScenarioError::Schema {
        file: file.to_string(),
        line,
        column,
        message: format!("{path}.radar: {}", one_line(e.message())),
    })
}

/// Check one radar table on its own, so an error names the file and line it is in.
fn parse_radar(loader: &Loader, t: &Spanned<toml::Table>, file: &str, path: &str) -> Result<(), ScenarioError> {
    let r: Result<RadarParams, _> = toml::Value::Table(t.get_ref().clone()).try_into();
    let Err(e) = r else {
        return Ok(());
    };
    let (line, column) = loader.place(file, t.span());
    let message = format!("{path}: {}", one_line(e.message()));
    if let Some(rest) = e.message().strip_prefix("unknown field `") {
        return Err(ScenarioError::UnknownField {
            file: file.to_string(),
            line,
            column,
            field: rest.split('`').next().unwrap_or_default().to_string(),
            message,
        });
    }
    Err(ScenarioError::Schema { file: file.to_string(), line, column, message })
}

/// The scenario the collected definitions describe, every value checked.
fn resolve(loader: &Loader, acc: Collected, top: &str, default_name: &str) -> Result<Scenario, ScenarioError> {
    let duration_s = resolve_duration(acc.duration_s.as_ref())?;
    let fidelity = resolve_fidelity(acc.fidelity)?;
    let ships = resolve_ships(loader, &acc.ships, acc.radar.as_ref(), top)?;
    let biases = match acc.biases {
        Some((b, file)) => {
            b.validate(ships.len(), &Ctx::new(&file, "biases"))?;
            b
        }
        None => crate::biases::Biases::default(),
    };
    let links = match acc.links {
        Some((l, file)) => {
            l.validate(ships.len(), &Ctx::new(&file, "links"))?;
            l
        }
        None => crate::links::Links::default(),
    };
    for (name, (t, file)) in &acc.types {
        validate_type(t, &Ctx::new(file, format!("aircraft_types.{name}")))?;
    }
    let (defs, formations, aircraft) = resolve_flights(acc.formations, acc.aircraft, &acc.types)?;
    check_unique_ids(&defs)?;
    // Target selection.
    let (selected, sel_file): (Vec<String>, String) = match acc.targets {
        Some((t, file)) => (t, file),
        None => (defs.iter().map(|d| d.id.clone()).collect(), top.to_string()),
    };
    let (targets, keep) = resolve_targets(&selected, &sel_file, &defs, &acc.types)?;
    let formations = formations.iter().filter_map(|f| prune_formation(f, &keep)).collect();
    let aircraft = aircraft.into_iter().filter(|a| keep.contains(a.id.as_str())).collect();
    let scenario = Scenario {
        name: acc.name.unwrap_or_else(|| default_name.to_string()),
        description: acc.description.unwrap_or_default(),
        duration_s,
        fidelity,
        ships,
        targets,
        formations,
        aircraft,
        biases,
        links,
    };
    scenario.validate()?;
    Ok(scenario)
}

/// The run duration set (checked), or the default.
fn resolve_duration(set: Option<&(f64, String)>) -> Result<f64, ScenarioError> {
    match set {
        Some((d, file)) => {
            validate_duration(*d, &Ctx::new(file, ""))?;
            Ok(*d)
        }
        None => Ok(DEFAULT_DURATION_S),
    }
}

/// The fidelity set (checked), or the default.
fn resolve_fidelity(set: Option<(Fidelity, String)>) -> Result<Fidelity, ScenarioError> {
    match set {
        Some((f, file)) => {
            validate_fidelity(&f, &Ctx::new(&file, "fidelity"))?;
            Ok(f)
        }
        None => Ok(Fidelity::default()),
    }
}

/// The ships, each with its radar (the fleet's, overridden by its own), checked; at least one.
fn resolve_ships(
    loader: &Loader,
    raw: &[From<RawShip>],
    fleet_radar: Option<&(Spanned<toml::Table>, String)>,
    top: &str,
) -> Result<Vec<Ship>, ScenarioError> {
    let mut ships = Vec::with_capacity(raw.len());
    for (n, s) in raw.iter().enumerate() {
        let ctx = Ctx::new(&s.file, format!("ships[{}]", s.index));
        let Some(id) = RadarId::parse(&s.item.id) else {
            return Err(ctx.err("id", format!("a radar id R1, R2, …, got `{}`", s.item.id)));
        };
        let radar = radar_params(loader, fleet_radar, s.item.radar.as_ref(), &s.file, &ctx.path)?;
        let ship = Ship {
            id,
            lat_deg: s.item.lat_deg,
            lon_deg: s.item.lon_deg,
            array_height_m: s.item.array_height_m,
            heading_deg: s.item.heading_deg,
            speed_mps: s.item.speed_mps,
            radar,
        };
        validate_ship(&ship, n, &ctx)?;
        ships.push(ship);
    }
    if ships.is_empty() {
        return Err(
            Ctx::new(top, "").err("ships", "at least one ship (define `[[ships]]` or include a file that does)")
        );
    }
    Ok(ships)
}

/// Aircraft types by name, each with the file that defines it.
type Types = BTreeMap<String, (AircraftType, String)>;

/// The aircraft type named `kind`, or an error listing the types defined.
fn type_of(types: &Types, kind: &str, ctx: &Ctx) -> Result<AircraftType, ScenarioError> {
    types.get(kind).map(|(t, _)| *t).ok_or_else(|| {
        let names: Vec<&str> = types.keys().map(String::as_str).collect();
        ctx.err("type", format!("one of the aircraft types defined ({}), got `{kind}`", names.join(", ")))
    })
}

/// A target as a flight defines it.
struct Def {
    /// Its id.
    id: String,
    /// Its aircraft type.
    kind: String,
    /// Its own mean RCS, if set.
    rcs_override: Option<f64>,
    /// The file that defines it.
    file: String,
    /// The key path of its id.
    path: String,
}

/// Every target the flights define (in definition order), the formations and the aircraft.
type Flights = (Vec<Def>, Vec<Formation>, Vec<Aircraft>);

/// Formations and aircraft checked, and every target they define, in definition order.
fn resolve_flights(
    formations: Vec<From<Formation>>,
    aircraft: Vec<From<Aircraft>>,
    types: &Types,
) -> Result<Flights, ScenarioError> {
    let mut defs: Vec<Def> = Vec::new();
    let mut checked_formations = Vec::with_capacity(formations.len());
    for f in formations {
        let ctx = Ctx::new(&f.file, format!("formations[{}]", f.index));
        validate_formation(&f.item, &ctx)?;
        type_of(types, &f.item.kind, &ctx)?;
        for (i, m) in f.item.members.iter().enumerate() {
            defs.push(Def {
                id: m.id.clone(),
                kind: f.item.kind.clone(),
                rcs_override: m.rcs_m2,
                file: f.file.clone(),
                path: format!("{}.members[{i}].id", ctx.path),
            });
        }
        let mut item = f.item;
        fix_references(&mut item);
        checked_formations.push(item);
    }
    let mut checked_aircraft = Vec::with_capacity(aircraft.len());
    for a in aircraft {
        let ctx = Ctx::new(&a.file, format!("aircraft[{}]", a.index));
        validate_aircraft(&a.item, &ctx)?;
        type_of(types, &a.item.kind, &ctx)?;
        defs.push(Def {
            id: a.item.id.clone(),
            kind: a.item.kind.clone(),
            rcs_override: a.item.rcs_m2,
            file: a.file.clone(),
            path: format!("{}.id", ctx.path),
        });
        checked_aircraft.push(a.item);
    }
    Ok((defs, checked_formations, checked_aircraft))
}

/// Every target id is defined once.
fn check_unique_ids(defs: &[Def]) -> Result<(), ScenarioError> {
    let mut seen: HashMap<&str, &str> = HashMap::new();
    for d in defs {
        if let Some(prev) = seen.insert(&d.id, &d.file) {
            return Err(ScenarioError::invalid(
                &d.file,
                &d.path,
                format!("a target id not defined before, `{}` is also defined in {prev}", d.id),
            ));
        }
    }
    Ok(())
}

/// The selected targets (at least one, each defined and selected once), and their ids.
fn resolve_targets<'s>(
    selected: &'s [String],
    sel_file: &str,
    defs: &[Def],
    types: &Types,
) -> Result<(Vec<Target>, HashSet<&'s str>), ScenarioError> {
    let sel_ctx = Ctx::new(sel_file, "");
    if selected.is_empty() {
        return Err(sel_ctx.err("targets", "at least one target"));
    }
    let mut targets = Vec::with_capacity(selected.len());
    let mut keep: HashSet<&str> = HashSet::new();
    for (i, id) in selected.iter().enumerate() {
        let Some(d) = defs.iter().find(|d| d.id == *id) else {
            let ids: Vec<&str> = defs.iter().map(|d| d.id.as_str()).collect();
            return Err(
                sel_ctx.err(&format!("targets[{i}]"), format!("a defined target ({}), got `{id}`", ids.join(", ")))
            );
        };
        if !keep.insert(id) {
            return Err(sel_ctx.err(&format!("targets[{i}]"), format!("each target once, `{id}` repeats")));
        }
        let ty = type_of(types, &d.kind, &sel_ctx)?;
        let rcs_m2 = d.rcs_override.unwrap_or(ty.rcs_m2);
        targets.push(Target {
            id: id.clone(),
            kind: d.kind.clone(),
            rcs_m2,
            envelope: ty.envelope(),
            // A target's own mean RCS scales its type's whole scattering matrix.
            polarimetry: ty.polarimetry.map(|p| p.scaled(rcs_m2 / ty.rcs_m2)),
        });
    }
    Ok((targets, keep))
}
