//! What stages produce and consume: tables, fields and files.

use std::collections::BTreeMap;
use std::fmt;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use crate::{Field, Schema, StageError, Table};

/// The kind of a product, as declared in a stage's inputs and outputs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ProductKind {
    /// A table, stored as Parquet.
    Table,
    /// A 2-D field, stored as `.npy` with a `.grid.json` sidecar.
    Field,
    /// Named files (figures, HTML), stored as they are.
    Files,
}

impl fmt::Display for ProductKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ProductKind::Table => "table",
            ProductKind::Field => "field",
            ProductKind::Files => "files",
        })
    }
}

/// Files a stage writes verbatim, keyed by file name (`fig7.svg`,
/// `index.html`); they land directly in the stage's output folder. A stage
/// handing files on to others (contact maps, figures) gives them an index:
/// a table declared as a [`Schema`] saying which file holds what, so the
/// reader gets typed rows instead of parsing a file of its own.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Files {
    pub files: BTreeMap<String, Vec<u8>>,
    /// The index, for an output declared with
    /// [`crate::OutputSpec::files_indexed`].
    pub index: Option<Table>,
}

impl Files {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn with(mut self, name: &str, bytes: Vec<u8>) -> Self {
        self.files.insert(name.to_owned(), bytes);
        self
    }

    /// The files with their index.
    pub fn with_index<S: Schema>(mut self, index: S) -> Self {
        self.index = Some(index.into_table());
        self
    }
}

/// One output of a stage.
#[derive(Clone, Debug, PartialEq)]
pub enum Product {
    Table(Table),
    Field(Field),
    Files(Files),
}

impl Product {
    pub fn kind(&self) -> ProductKind {
        match self {
            Product::Table(_) => ProductKind::Table,
            Product::Field(_) => ProductKind::Field,
            Product::Files(_) => ProductKind::Files,
        }
    }
}

/// The products a stage receives, by input name.
#[derive(Clone, Debug, Default)]
pub struct Inputs {
    items: BTreeMap<String, Arc<Product>>,
}

impl Inputs {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn insert(&mut self, name: &str, product: Arc<Product>) {
        self.items.insert(name.to_owned(), product);
    }

    /// Builder for tests and library use.
    pub fn with(mut self, name: &str, product: Product) -> Self {
        self.insert(name, Arc::new(product));
        self
    }

    pub fn get(&self, name: &str) -> Option<&Product> {
        self.items.get(name).map(|p| p.as_ref())
    }

    pub fn names(&self) -> impl Iterator<Item = &str> {
        self.items.keys().map(String::as_str)
    }

    /// The products of a many-input (`Arity::Many`), as (label, product) in
    /// label order: `responses: { T1: a, T2: b }` gives `[("T1", a), ("T2", b)]`.
    pub fn labelled(&self, name: &str) -> Vec<(&str, &Product)> {
        let prefix = format!("{name}.");
        self.items
            .iter()
            .filter_map(|(k, v)| k.strip_prefix(&prefix).map(|label| (label, v.as_ref())))
            .collect()
    }

    fn require(&self, name: &str) -> Result<&Product, StageError> {
        self.get(name)
            .ok_or_else(|| StageError::MissingInput(name.to_owned()))
    }

    pub fn table(&self, name: &str) -> Result<&Table, StageError> {
        match self.require(name)? {
            Product::Table(t) => Ok(t),
            other => Err(wrong_kind(name, ProductKind::Table, other)),
        }
    }

    /// A table input read into its schema; a missing or mistyped column is
    /// an error naming the input.
    pub fn read<S: Schema>(&self, name: &str) -> Result<S, StageError> {
        S::from_table(self.table(name)?).map_err(|cause| StageError::InputTable {
            input: name.to_owned(),
            cause,
        })
    }

    pub fn field(&self, name: &str) -> Result<&Field, StageError> {
        match self.require(name)? {
            Product::Field(f) => Ok(f),
            other => Err(wrong_kind(name, ProductKind::Field, other)),
        }
    }

    /// A field input that must be a 2-D map: a line scan (see
    /// [`Field::is_line_scan`]) is refused naming the stage `kind` and the
    /// input, as every stage that models contact on an area must.
    pub fn areal_field(&self, name: &str, kind: &'static str) -> Result<&Field, StageError> {
        let field = self.field(name)?;
        if field.is_line_scan() {
            return Err(StageError::LineScan {
                kind,
                input: name.to_owned(),
                nx: field.nx(),
                ny: field.ny(),
            });
        }
        Ok(field)
    }

    pub fn files(&self, name: &str) -> Result<&Files, StageError> {
        match self.require(name)? {
            Product::Files(f) => Ok(f),
            other => Err(wrong_kind(name, ProductKind::Files, other)),
        }
    }

    /// A files input with its index read into schema `S`; files without an
    /// index, or an index without a column of `S`, are an error naming the
    /// input.
    pub fn indexed_files<S: Schema>(&self, name: &str) -> Result<(&Files, S), StageError> {
        let files = self.files(name)?;
        let index = files
            .index
            .as_ref()
            .ok_or_else(|| StageError::NoIndex(name.to_owned()))?;
        let rows = S::from_table(index).map_err(|cause| StageError::InputTable {
            input: name.to_owned(),
            cause,
        })?;
        Ok((files, rows))
    }

    /// The products of a doubly labelled input ([`crate::Arity::Nested`]) as
    /// (sample, model, product), in label order:
    /// `responses: { T1: { icm: a } }` gives `[("T1", "icm", a)]`.
    pub fn nested(&self, name: &str) -> Vec<(&str, &str, &Product)> {
        self.labelled(name)
            .into_iter()
            .filter_map(|(labels, p)| {
                let (sample, model) = labels.split_once('.')?;
                Some((sample, model, p))
            })
            .collect()
    }
}

fn wrong_kind(name: &str, expected: ProductKind, found: &Product) -> StageError {
    StageError::InputKind {
        name: name.to_owned(),
        expected,
        found: found.kind(),
    }
}

/// The products a stage returns, by output name.
#[derive(Clone, Debug, Default)]
pub struct Outputs {
    items: BTreeMap<String, Product>,
}

impl Outputs {
    pub fn new() -> Self {
        Self::default()
    }

    pub fn table(mut self, name: &str, table: Table) -> Self {
        self.items.insert(name.to_owned(), Product::Table(table));
        self
    }

    pub fn field(mut self, name: &str, field: Field) -> Self {
        self.items.insert(name.to_owned(), Product::Field(field));
        self
    }

    pub fn files(mut self, name: &str, files: Files) -> Self {
        self.items.insert(name.to_owned(), Product::Files(files));
        self
    }

    pub fn insert(&mut self, name: &str, product: Product) {
        self.items.insert(name.to_owned(), product);
    }

    pub fn get(&self, name: &str) -> Option<&Product> {
        self.items.get(name)
    }

    /// The output `name` if it is a table.
    pub fn get_table(&self, name: &str) -> Option<&Table> {
        match self.items.get(name) {
            Some(Product::Table(t)) => Some(t),
            _ => None,
        }
    }

    /// The output `name` if it is a set of files.
    pub fn get_files(&self, name: &str) -> Option<&Files> {
        match self.items.get(name) {
            Some(Product::Files(f)) => Some(f),
            _ => None,
        }
    }

    pub fn iter(&self) -> impl Iterator<Item = (&str, &Product)> {
        self.items.iter().map(|(k, v)| (k.as_str(), v))
    }

    pub fn into_inner(self) -> BTreeMap<String, Product> {
        self.items
    }

    pub fn len(&self) -> usize {
        self.items.len()
    }

    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }
}
