//! WGSL modules: the shared shader code as named modules that shaders import, composed with
//! naga_oil (Bevy's shader composer).
//!
//! A module's text starts with `#define_import_path crate::name` (`gpu::prelude`,
//! `scene::shading`, `height_maps::search`); a shader takes what it uses by name,
//! `#import gpu::prelude::{PI, ray_box}`, or the whole module, `#import gpu::distance_map` and then
//! `distance_map::hit_from_outside(…)`. Names are namespaced: the composed shader holds each module's items
//! under a mangled name, so a module's `PI` or `MISS` clashes with nothing in the user's own
//! WGSL, and two modules may use the same name. Values a shader is specialised with (the first
//! binding of a block, the count of maps in an array) are shader definitions, `#{FIRST}` in the
//! text, given at composition ([`Def`]); `#ifdef` selects code.
//!
//! Why naga_oil and not WESL: naga_oil 0.23 is built on naga 30, the naga wgpu 30 uses, so the
//! composed `naga::Module` goes to wgpu as IR (`ShaderSource::Naga`), without printing and
//! parsing WGSL again; WESL's Rust compiler (wesl 0.6) needs a newer Rust than the workspace's and
//! composes to WGSL text.
//!
//! [`Module`] names a module's text and the modules it imports; [`compose`] makes a `naga::Module`
//! of a shader; [`crate::shader`] makes the wgpu shader module. Conformance tests compose their
//! kernels through the same functions, so they run the WGSL the techniques run.

use std::borrow::Cow;
use std::collections::HashMap;
use std::sync::Mutex;

use naga_oil::compose::{
    ComposableModuleDescriptor, Composer, ComposerError, ImportDefinition, NagaModuleDescriptor,
    ShaderDefValue, ShaderLanguage,
};

/// A WGSL module other shaders import: its text (starting with `#define_import_path`), the file
/// it comes from (for error messages) and the modules its own `#import`s name.
#[derive(Clone, Debug)]
pub struct Module {
    /// The WGSL text.
    pub source: Cow<'static, str>,
    /// The file the text comes from, as error messages print it.
    pub file: &'static str,
    /// The modules this one imports (they are added to the composer before it).
    pub imports: &'static [&'static Module],
}

impl Module {
    /// A module of static text.
    pub const fn new(
        source: &'static str,
        file: &'static str,
        imports: &'static [&'static Module],
    ) -> Self {
        Self {
            source: Cow::Borrowed(source),
            file,
            imports,
        }
    }

    /// The same module with other text (a conformance test's deliberately broken copy).
    pub fn with_source(&self, source: String) -> Self {
        Self {
            source: Cow::Owned(source),
            ..self.clone()
        }
    }

    /// The name in the text's `#define_import_path`.
    pub fn name(&self) -> String {
        let (name, _, _) = naga_oil::compose::get_preprocessor_data(&self.source);
        name.unwrap_or_else(|| panic!("{}: a WGSL module needs #define_import_path", self.file))
    }
}

/// A shader definition's value: `#{NAME}` in a module or shader is replaced by it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Def {
    Bool(bool),
    Int(i32),
    UInt(u32),
}

/// A shader to compose: its own text, the modules it imports and its definitions.
#[derive(Clone, Copy, Debug)]
pub struct Shader<'a> {
    /// What error messages and wgpu's labels call it.
    pub label: &'a str,
    /// The shader's own WGSL (entry points and whatever is not shared).
    pub source: &'a str,
    /// The modules its `#import`s name (their own imports come with them).
    pub imports: &'a [&'a Module],
    /// Values for its `#{NAME}`s and `#ifdef`s.
    pub defs: &'a [(&'a str, Def)],
    /// Modules whose `override fn`s replace a module's `virtual fn` everywhere in the shader
    /// (naga_oil's additional imports: an override takes effect only in the shader itself or
    /// in a module given so, not in one reached by `#import`).
    pub overrides: &'a [&'a Module],
}

impl<'a> Shader<'a> {
    /// A shader importing only `gpu`'s modules (which are always there) and using no definitions.
    pub fn new(label: &'a str, source: &'a str) -> Self {
        Self {
            label,
            source,
            imports: &[],
            defs: &[],
            overrides: &[],
        }
    }

    /// The same shader importing `imports`.
    pub fn importing(self, imports: &'a [&'a Module]) -> Self {
        Self { imports, ..self }
    }

    /// The same shader with definitions.
    pub fn with_defs(self, defs: &'a [(&'a str, Def)]) -> Self {
        Self { defs, ..self }
    }

    /// The same shader with `overrides`' `override fn`s in effect (a per-object search that
    /// supplies the functions a shared driver declares `virtual`).
    pub fn overriding(self, overrides: &'a [&'a Module]) -> Self {
        Self { overrides, ..self }
    }
}

/// A shader of its text alone (a kernel importing only `gpu`'s modules).
impl<'a> From<&'a str> for Shader<'a> {
    fn from(source: &'a str) -> Self {
        Shader::new("shader", source)
    }
}

impl<'a> From<&'a String> for Shader<'a> {
    fn from(source: &'a String) -> Self {
        Shader::new("shader", source)
    }
}

/// Composes a shader: its text with every module it imports, as one naga module. An error is
/// the composer's report (file, line and the offending text) as one message.
pub fn compose(shader: &Shader<'_>) -> Result<naga::Module, String> {
    let mut cache = COMPOSER
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    let cache = cache.get_or_insert_with(ComposerCache::new);
    for module in crate::gpu_modules()
        .into_iter()
        .chain(shader.imports.iter().copied())
        .chain(shader.overrides.iter().copied())
    {
        cache.add(module)?;
    }
    let additional_imports: Vec<ImportDefinition> = shader
        .overrides
        .iter()
        .map(|module| ImportDefinition {
            import: module.name(),
            items: Vec::new(),
        })
        .collect();
    let shader_defs = shader
        .defs
        .iter()
        .map(|(name, def)| (name.to_string(), def.value()))
        .collect();
    let source = merge_imports(shader.source);
    cache
        .composer
        .make_naga_module(NagaModuleDescriptor {
            source: &source,
            file_path: shader.label,
            shader_defs,
            additional_imports: &additional_imports,
            ..Default::default()
        })
        .map_err(|error| cache.report(error))
}

/// A shader made of parts (a pass's entry points after a shared vertex stage) may import one
/// item or module in two parts; the composer rejects an item imported twice ("ambiguous
/// import"), so the `#import path::{items}` lines are merged into one per path, written on the
/// lines the imports took (there are at least as many), and a module imported whole is imported
/// once: error messages keep their line numbers.
fn merge_imports(source: &str) -> String {
    let mut lines: Vec<String> = source.lines().map(String::from).collect();
    let mut import_lines = Vec::new();
    let mut items: Vec<(String, Vec<String>)> = Vec::new();
    let mut whole_modules: Vec<(usize, String)> = Vec::new();
    for (number, line) in lines.iter().enumerate() {
        let Some(spec) = line.trim().strip_prefix("#import ") else {
            continue;
        };
        let Some((path, list)) = parse_item_import(spec) else {
            // A whole module (`#import gpu::distance_map`): once is enough.
            whole_modules.push((number, spec.trim().to_string()));
            continue;
        };
        match items.iter_mut().find(|(known, _)| *known == path) {
            Some((_, known)) => known.extend(list),
            None => items.push((path, list)),
        }
        import_lines.push(number);
    }
    for (k, number) in import_lines.into_iter().enumerate() {
        lines[number] = match items.get_mut(k) {
            Some((path, list)) => {
                list.sort();
                list.dedup();
                format!("#import {path}::{{{}}}", list.join(", "))
            }
            None => String::new(),
        };
    }
    for (k, (number, spec)) in whole_modules.iter().enumerate() {
        if whole_modules[..k]
            .iter()
            .any(|(_, earlier)| earlier == spec)
        {
            lines[*number] = String::new();
        }
    }
    lines.join("\n")
}

/// `path::{a, b}` or `path::item` (the forms a module's items are imported by) as the path and
/// the items; a whole-module import (`gpu::distance_map`, `gpu::distance_map as h`) is left as written.
fn parse_item_import(spec: &str) -> Option<(String, Vec<String>)> {
    let spec = spec.trim();
    if let Some((path, list)) = spec.split_once("::{") {
        let list = list.trim_end().strip_suffix('}')?;
        let items = list
            .split(',')
            .map(str::trim)
            .filter(|item| !item.is_empty());
        return Some((path.to_string(), items.map(String::from).collect()));
    }
    let (path, item) = spec.rsplit_once("::")?;
    // `gpu::distance_map` is a module, `gpu::prelude::PI` an item: items of our modules are the
    // third segment.
    (path.contains("::") && !item.contains(' ')).then(|| (path.to_string(), vec![item.to_string()]))
}

impl Def {
    fn value(self) -> ShaderDefValue {
        match self {
            Def::Bool(b) => ShaderDefValue::Bool(b),
            Def::Int(i) => ShaderDefValue::Int(i),
            Def::UInt(u) => ShaderDefValue::UInt(u),
        }
    }
}

/// One composer for the process: a module is parsed once, when a shader first imports it, and
/// reused by every shader after (the composer does not depend on the device).
static COMPOSER: Mutex<Option<ComposerCache>> = Mutex::new(None);

struct ComposerCache {
    composer: Composer,
    /// Each added module's text, so a module imported with other text (a test's broken copy)
    /// replaces the one added before.
    sources: HashMap<String, Cow<'static, str>>,
}

impl ComposerCache {
    fn new() -> Self {
        // The device validates the composed module against its own features; the composer's
        // validation (which makes its error messages point at the right line) allows all.
        let composer = Composer::default().with_capabilities(naga::valid::Capabilities::all());
        Self {
            composer,
            sources: HashMap::new(),
        }
    }

    /// Adds `module` and, first, what it imports; a module already added with the same text
    /// is kept.
    fn add(&mut self, module: &Module) -> Result<(), String> {
        for import in module.imports {
            self.add(import)?;
        }
        let name = module.name();
        if self
            .sources
            .get(&name)
            .is_some_and(|source| *source == module.source)
        {
            return Ok(());
        }
        // Other text under a known name: drop it and what was composed over it.
        self.composer.remove_composable_module(&name);
        let composer = &self.composer;
        self.sources
            .retain(|known, _| composer.contains_module(known));
        let added = self
            .composer
            .add_composable_module(ComposableModuleDescriptor {
                source: &module.source,
                file_path: module.file,
                language: ShaderLanguage::Wgsl,
                ..Default::default()
            })
            .map(|_| ());
        added.map_err(|error| self.report(error))?;
        self.sources.insert(name, module.source.clone());
        Ok(())
    }

    fn report(&self, error: ComposerError) -> String {
        error.emit_to_string(&self.composer)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn imports_of_one_item_in_two_parts_are_merged() {
        let merged = merge_imports(
            "#import gpu::prelude::{PI, ray_box}\nfn a() {}\n#import gpu::prelude::PI\n\
             #import gpu::distance_map\n#import gpu::prelude::luminance\n#import gpu::distance_map",
        );
        assert_eq!(
            merged,
            "#import gpu::prelude::{PI, luminance, ray_box}\nfn a() {}\n\n\
             #import gpu::distance_map\n\n"
        );
    }

    /// The prelude's names are namespaced: a shader may declare its own `PI` and `MISS` and
    /// still import the prelude's `ray_box`, which uses the prelude's `MISS`.
    #[test]
    fn a_shader_may_reuse_the_names_of_what_it_imports() {
        let source = "#import gpu::prelude::ray_box
const PI: f32 = 3.0;
const MISS: f32 = -2.0;
@compute @workgroup_size(1)
fn main() {
    let t = ray_box(vec3f(0.0), vec3f(1.0, 0.0, 0.0), vec3f(-1.0), vec3f(1.0));
    let x = t.x * PI + MISS;
}
";
        let module = compose(&Shader::new("names", source)).expect("composes");
        let constants: Vec<_> = module
            .constants
            .iter()
            .filter_map(|(_, c)| c.name.clone())
            .collect();
        assert!(constants.contains(&"PI".to_string()), "{constants:?}");
        assert!(
            constants
                .iter()
                .filter(|name| name.starts_with("MISS"))
                .count()
                == 2,
            "{constants:?}"
        );
    }

    #[test]
    fn an_unknown_name_is_reported_with_its_line() {
        let error = compose(&Shader::new(
            "broken pass",
            "fn f() -> f32 {\n    return PI;\n}\n",
        ))
        .expect_err("PI is not imported");
        assert!(error.contains("broken pass:2"), "{error}");
        assert!(error.contains("PI"), "{error}");
    }

    #[test]
    fn definitions_specialise_the_text() {
        let source = "@group(#{GROUP}) @binding(0) var<uniform> u: vec4f;
@compute @workgroup_size(1)
fn main() { let x = u.x; }
";
        let defs = [("GROUP", Def::UInt(3))];
        let module = compose(&Shader::new("defs", source).with_defs(&defs)).expect("composes");
        let (_, global) = module.global_variables.iter().next().expect("one global");
        assert_eq!(global.binding.as_ref().map(|b| b.group), Some(3));
    }

    static HOOKED: Module = Module::new(
        "#define_import_path probe::hooked
virtual fn kind(i: u32) -> u32 { return 7u; }
fn twice_kind(i: u32) -> u32 { return 2u * kind(i); }
",
        "hooked.wgsl",
        &[],
    );

    static OVERRIDING: Module = Module::new(
        "#define_import_path probe::overriding
#import probe::hooked
override fn probe::hooked::kind(i: u32) -> u32 { return i + 1u; }
",
        "overriding.wgsl",
        &[&HOOKED],
    );

    /// A module given as an override replaces the virtual function for every caller, the
    /// module's own included; without it the module's own body is called.
    #[test]
    fn an_override_module_replaces_a_virtual_function() {
        let source = "#import probe::hooked::twice_kind
@compute @workgroup_size(1)
fn main() { let k = twice_kind(3u); }
";
        let calls_of_twice_kind = |module: &naga::Module| {
            let (_, twice) = module
                .functions
                .iter()
                .find(|(_, f)| {
                    f.name
                        .as_deref()
                        .is_some_and(|n| n.starts_with("twice_kind"))
                })
                .expect("twice_kind");
            twice
                .body
                .iter()
                .find_map(|statement| match statement {
                    naga::Statement::Call { function, .. } => {
                        module.functions[*function].name.clone()
                    }
                    _ => None,
                })
                .expect("a call")
        };
        let imports = [&HOOKED];
        let plain = Shader::new("plain", source).importing(&imports);
        let plain = compose(&plain).expect("composes");
        let overrides = [&OVERRIDING];
        let overridden = Shader::new("overridden", source)
            .importing(&imports)
            .overriding(&overrides);
        let overridden = compose(&overridden).expect("composes");
        let (before, after) = (
            calls_of_twice_kind(&plain),
            calls_of_twice_kind(&overridden),
        );
        assert!(!before.contains("_vrt_"), "{before}");
        assert!(after.contains("_vrt_"), "{after}");
    }
}
