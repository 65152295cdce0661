//! `#[derive(Choice)]`: a fieldless enum read and written by name.

use proc_macro2::{Ident, TokenStream};
use quote::quote;
use syn::{Data, DeriveInput, Fields, LitStr, Variant, spanned::Spanned};

use crate::docs::{doc_text, kebab_case};

/// One variant as a choice: its identifier, the name it is read and
/// written as, and its doc comment.
struct Named {
    ident: Ident,
    name: String,
    doc: String,
}

pub fn expand(item: TokenStream) -> syn::Result<TokenStream> {
    let input: DeriveInput = syn::parse2(item)?;
    let ident = &input.ident;
    let Data::Enum(data) = &input.data else {
        return Err(syn::Error::new(
            input.span(),
            "Choice is derived for fieldless enums",
        ));
    };
    let variants = data
        .variants
        .iter()
        .map(named)
        .collect::<syn::Result<Vec<_>>>()?;
    let choice = choice_impls(ident, &variants);
    let serde = serde_impls(ident);
    let param_value = param_value_impl(ident);
    Ok(quote! { #choice #serde #param_value })
}

/// A unit variant with its name: kebab case, or `#[choice(name = "...")]`.
fn named(variant: &Variant) -> syn::Result<Named> {
    if !matches!(variant.fields, Fields::Unit) {
        return Err(syn::Error::new(
            variant.span(),
            "Choice variants carry no data",
        ));
    }
    let mut name = kebab_case(&variant.ident.to_string());
    for attr in variant.attrs.iter().filter(|a| a.path().is_ident("choice")) {
        attr.parse_nested_meta(|meta| {
            if meta.path.is_ident("name") {
                name = meta.value()?.parse::<LitStr>()?.value();
                Ok(())
            } else {
                Err(meta.error("unknown #[choice] option (expected `name = \"...\"`)"))
            }
        })?;
    }
    Ok(Named {
        ident: variant.ident.clone(),
        name,
        doc: doc_text(&variant.attrs),
    })
}

/// `Choice` (the variants' names and docs), and `Display`/`FromStr` by name.
fn choice_impls(ident: &Ident, variants: &[Named]) -> TokenStream {
    let docs = variants.iter().map(|Named { name, doc, .. }| {
        quote! { ::hypercontact_core::param::ChoiceDoc { name: #name, doc: #doc } }
    });
    let to_name = variants
        .iter()
        .map(|Named { ident: v, name, .. }| quote! { #ident::#v => #name });
    let from_name = variants.iter().map(|Named { ident: v, name, .. }| {
        quote! { #name => ::core::option::Option::Some(#ident::#v) }
    });
    quote! {
        impl ::hypercontact_core::param::Choice for #ident {
            const VARIANTS: &'static [::hypercontact_core::param::ChoiceDoc] = &[#(#docs),*];

            fn name(&self) -> &'static str {
                match self { #(#to_name),* }
            }

            fn from_name(name: &str) -> ::core::option::Option<Self> {
                match name {
                    #(#from_name,)*
                    _ => ::core::option::Option::None,
                }
            }
        }

        impl ::core::fmt::Display for #ident {
            fn fmt(&self, f: &mut ::core::fmt::Formatter<'_>) -> ::core::fmt::Result {
                f.write_str(::hypercontact_core::param::Choice::name(self))
            }
        }

        impl ::core::str::FromStr for #ident {
            type Err = ::hypercontact_core::param::UnknownChoice;

            fn from_str(s: &str) -> ::core::result::Result<Self, Self::Err> {
                ::hypercontact_core::param::parse_choice(s)
            }
        }
    }
}

/// Serde as the name: what a pipeline's YAML holds.
fn serde_impls(ident: &Ident) -> TokenStream {
    quote! {
        impl ::hypercontact_core::__private::serde::Serialize for #ident {
            fn serialize<S: ::hypercontact_core::__private::serde::Serializer>(
                &self,
                serializer: S,
            ) -> ::core::result::Result<S::Ok, S::Error> {
                serializer.serialize_str(::hypercontact_core::param::Choice::name(self))
            }
        }

        impl<'de> ::hypercontact_core::__private::serde::Deserialize<'de> for #ident {
            fn deserialize<D: ::hypercontact_core::__private::serde::Deserializer<'de>>(
                deserializer: D,
            ) -> ::core::result::Result<Self, D::Error> {
                ::hypercontact_core::param::deserialize_choice(deserializer)
            }
        }
    }
}

/// A choice as a parameter: documented by its variants, always valid (the
/// name was checked when read), holding no input file.
fn param_value_impl(ident: &Ident) -> TokenStream {
    quote! {
        impl ::hypercontact_core::ParamValue for #ident {
            fn type_doc() -> ::hypercontact_core::param::TypeDoc {
                ::hypercontact_core::param::TypeDoc::Choice(
                    <Self as ::hypercontact_core::param::Choice>::VARIANTS,
                )
            }

            fn validate_at(
                &self,
                _prefix: &str,
            ) -> ::core::result::Result<(), ::hypercontact_core::ParamError> {
                ::core::result::Result::Ok(())
            }

            fn visit_paths(
                &mut self,
                _prefix: &str,
                _visit: &mut dyn ::core::ops::FnMut(&str, &mut ::hypercontact_core::InputPath),
            ) {
            }
        }
    }
}
