//! Derives for hypercontact's stage declarations, so that a stage states each
//! fact once and everything else is generated from it:
//!
//! - [`params`] (attribute): a parameter struct. Each field carries its doc
//!   comment, default, unit and range; from that one declaration come the serde
//!   shape (unknown keys rejected, defaults filled in), the checks, the
//!   `hypercontact stages` text and JSON, the "required" flag, and the walk
//!   that finds every input file (so its content enters the cache key).
//! - [`Choice`] (derive): a fieldless enum read and written as one of its
//!   names (`hyperelastic`, `UT`), with its variants' docs listed by `stages`.
//! - [`Schema`] (derive): a table as a struct of columns; the column list a
//!   stage declares and the builder/reader are the same struct.
//!
//! The generated code names the core crate as `::hypercontact_core`.

mod choice;
mod docs;
mod flatten;
mod params;
mod schema;

use proc_macro::TokenStream;

/// Declares a parameter struct (see the crate docs). Field options, in
/// `#[param(...)]`: `default = EXPR`, `unit = "m"`, `range = LO..=HI` (any
/// Rust range of numbers; floats must also be finite), `positive`,
/// `check = path` (a `fn(&T) -> Result<(), String>` for this field),
/// `rename = "UT"`, `flatten` (the field is another `#[params]` struct
/// whose keys stand at this level, checked at this level; it must have a
/// default for each of its parameters). Struct option, in `#[params(check = path)]`: a
/// `fn(&Self) -> Result<(), ParamError>` for checks across fields.
/// A field without `default` that is not an `Option` is required.
#[proc_macro_attribute]
pub fn params(args: TokenStream, item: TokenStream) -> TokenStream {
    params::expand(args.into(), item.into())
        .unwrap_or_else(syn::Error::into_compile_error)
        .into()
}

/// A fieldless enum as a parameter choice; `#[choice(name = "UT")]` on a
/// variant overrides its kebab-case name.
#[proc_macro_derive(Choice, attributes(choice))]
pub fn derive_choice(item: TokenStream) -> TokenStream {
    choice::expand(item.into())
        .unwrap_or_else(syn::Error::into_compile_error)
        .into()
}

/// A table schema: a struct of `Vec<f64>`, `Vec<i64>` or `Vec<String>`
/// fields, one per column in order, each with `#[column(unit = "m")]` where
/// it has a unit and a doc comment; `#[column(flatten)]` on a field of
/// another schema's type splices its columns in at that place.
#[proc_macro_derive(Schema, attributes(column))]
pub fn derive_schema(item: TokenStream) -> TokenStream {
    schema::expand(item.into())
        .unwrap_or_else(syn::Error::into_compile_error)
        .into()
}
