//! `#[derive(Schema)]`: a table declared as a struct of columns.
//!
//! A field marked `#[column(flatten)]` holds another schema whose columns
//! stand, in order, where the field stands: how every contact model's table
//! is `ResponseTable` plus its own columns, declared once.

use proc_macro2::TokenStream;
use quote::quote;
use syn::{Data, DeriveInput, Field, Fields, LitStr, spanned::Spanned};

use crate::docs::doc_text;

/// What `#[column(...)]` says about one field.
struct ColumnOptions {
    name: String,
    unit: String,
    flatten: bool,
}

fn column_options(field: &Field) -> syn::Result<ColumnOptions> {
    let ident = field.ident.as_ref().expect("named fields have names");
    let mut options = ColumnOptions {
        name: ident.to_string(),
        unit: String::new(),
        flatten: false,
    };
    for attr in field.attrs.iter().filter(|a| a.path().is_ident("column")) {
        attr.parse_nested_meta(|meta| {
            if meta.path.is_ident("unit") {
                options.unit = meta.value()?.parse::<LitStr>()?.value();
            } else if meta.path.is_ident("name") {
                options.name = meta.value()?.parse::<LitStr>()?.value();
            } else if meta.path.is_ident("flatten") {
                options.flatten = true;
            } else {
                return Err(meta.error("unknown #[column] option (expected unit, name or flatten)"));
            }
            Ok(())
        })?;
    }
    if options.flatten && (!options.unit.is_empty() || *ident != options.name) {
        return Err(syn::Error::new(
            field.span(),
            "a flattened schema brings its own column names and units",
        ));
    }
    Ok(options)
}

pub fn expand(item: TokenStream) -> syn::Result<TokenStream> {
    let input: DeriveInput = syn::parse2(item)?;
    let ident = &input.ident;
    if !input.generics.params.is_empty() {
        return Err(syn::Error::new(
            input.generics.span(),
            "Schema is derived for structs without generics",
        ));
    }
    let Data::Struct(data) = &input.data else {
        return Err(syn::Error::new(
            input.span(),
            "Schema is derived for structs",
        ));
    };
    let Fields::Named(named) = &data.fields else {
        return Err(syn::Error::new(
            input.span(),
            "Schema needs named fields, one per column",
        ));
    };
    let mut parts = Vec::new();
    let mut builds = Vec::new();
    let mut reads = Vec::new();
    for field in &named.named {
        let field_ident = field.ident.as_ref().expect("named fields have names");
        let ty = &field.ty;
        let ColumnOptions {
            name,
            unit,
            flatten,
        } = column_options(field)?;
        if flatten {
            parts.push(quote! { <#ty as ::hypercontact_core::Schema>::COLUMNS });
            builds.push(quote! {
                table.extend(::hypercontact_core::Schema::into_table(self.#field_ident));
            });
            reads.push(quote! {
                #field_ident: <#ty as ::hypercontact_core::Schema>::from_table(table)?
            });
            continue;
        }
        let doc = doc_text(&field.attrs);
        parts.push(quote! {
            &[::hypercontact_core::ColumnSpec {
                name: #name,
                dtype: <#ty as ::hypercontact_core::schema::ColumnType>::DTYPE,
                unit: #unit,
                doc: #doc,
            }]
        });
        builds.push(quote! {
            table.push(#name, ::hypercontact_core::schema::ColumnType::into_column(self.#field_ident));
        });
        reads.push(quote! {
            #field_ident: <#ty as ::hypercontact_core::schema::ColumnType>::read(table, #name)?
        });
    }
    Ok(quote! {
        impl ::hypercontact_core::Schema for #ident {
            const COLUMNS: &'static [::hypercontact_core::ColumnSpec] = {
                const PARTS: &[&[::hypercontact_core::ColumnSpec]] = &[#(#parts),*];
                const ALL: [::hypercontact_core::ColumnSpec;
                    ::hypercontact_core::const_concat::total_len(PARTS)] =
                    ::hypercontact_core::const_concat::concat(
                        PARTS,
                        ::hypercontact_core::ColumnSpec::str("", ""),
                    );
                &ALL
            };

            fn into_table(self) -> ::hypercontact_core::Table {
                let mut table = ::hypercontact_core::Table::new();
                #(#builds)*
                table
            }

            fn from_table(
                table: &::hypercontact_core::Table,
            ) -> ::core::result::Result<Self, ::hypercontact_core::TableError> {
                ::core::result::Result::Ok(Self { #(#reads),* })
            }
        }
    })
}
