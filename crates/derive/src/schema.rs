//! `#[derive(Schema)]`: a table declared as a struct of columns.

use proc_macro2::TokenStream;
use quote::quote;
use syn::{Data, DeriveInput, Fields, LitStr, spanned::Spanned};

use crate::docs::doc_text;

pub fn expand(item: TokenStream) -> syn::Result<TokenStream> {
    let input: DeriveInput = syn::parse2(item)?;
    let ident = &input.ident;
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
    let mut specs = Vec::new();
    let mut builds = Vec::new();
    let mut reads = Vec::new();
    for field in &named.named {
        let field_ident = field.ident.as_ref().expect("named fields have names");
        let ty = &field.ty;
        let mut name = field_ident.to_string();
        let mut unit = String::new();
        for attr in field.attrs.iter().filter(|a| a.path().is_ident("column")) {
            attr.parse_nested_meta(|meta| {
                if meta.path.is_ident("unit") {
                    unit = meta.value()?.parse::<LitStr>()?.value();
                } else if meta.path.is_ident("name") {
                    name = meta.value()?.parse::<LitStr>()?.value();
                } else {
                    return Err(meta.error("unknown #[column] option (expected unit or name)"));
                }
                Ok(())
            })?;
        }
        let doc = doc_text(&field.attrs);
        specs.push(quote! {
            ::hypercontact_core::ColumnSpec {
                name: #name,
                dtype: <#ty as ::hypercontact_core::schema::ColumnType>::DTYPE,
                unit: #unit,
                doc: #doc,
            }
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
            const COLUMNS: &'static [::hypercontact_core::ColumnSpec] = &[#(#specs),*];

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
