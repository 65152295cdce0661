//! `#[derive(Choice)]`: a fieldless enum read and written by name.

use proc_macro2::TokenStream;
use quote::quote;
use syn::{Data, DeriveInput, Fields, LitStr, spanned::Spanned};

use crate::docs::{doc_text, kebab_case};

pub fn expand(item: TokenStream) -> syn::Result<TokenStream> {
    let input: DeriveInput = syn::parse2(item)?;
    let ident = &input.ident;
    let Data::Enum(data) = &input.data else {
        return Err(syn::Error::new(
            input.span(),
            "Choice is derived for fieldless enums",
        ));
    };
    let mut variants = Vec::new();
    for variant in &data.variants {
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
        variants.push((variant.ident.clone(), name, doc_text(&variant.attrs)));
    }
    let docs = variants.iter().map(|(_, name, doc)| {
        quote! { ::hypercontact_core::param::ChoiceDoc { name: #name, doc: #doc } }
    });
    let to_name = variants
        .iter()
        .map(|(v, name, _)| quote! { #ident::#v => #name });
    let from_name = variants
        .iter()
        .map(|(v, name, _)| quote! { #name => ::core::option::Option::Some(#ident::#v) });

    Ok(quote! {
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
    })
}
