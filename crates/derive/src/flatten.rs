//! The key-by-key reader `#[params]` generates: the `Flatten` impl every
//! parameter struct gets (so any of them can be flattened into another), and
//! for a struct with `#[param(flatten)]` blocks its `Deserialize`, which
//! hands each key to the field or block that declares it (see core's
//! `param::flatten` for why serde's own flatten does not serve).

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::{Ident, Visibility};

use crate::params::ParamField;

const CORE: &str = "::hypercontact_core::param::flatten";

fn core_path() -> TokenStream {
    CORE.parse().expect("a path")
}

/// The `Flatten` impl and its slots struct.
pub fn flatten_impl(ident: &Ident, vis: &Visibility, fields: &[ParamField]) -> TokenStream {
    let core = core_path();
    let slots = format_ident!("__{}Slots", ident);
    let slot_fields = fields.iter().map(|f| {
        let (field, ty) = (&f.ident, &f.ty);
        if f.options.flatten {
            quote!(#vis #field: <#ty as #core::Flatten>::Slots)
        } else {
            quote!(#vis #field: ::core::option::Option<#ty>)
        }
    });
    let parts = fields.iter().map(|f| {
        let ty = &f.ty;
        let name = &f.name;
        if f.options.flatten {
            quote!(<#ty as #core::Flatten>::FIELDS)
        } else {
            quote!(&[#name])
        }
    });
    let own_keys = fields.iter().filter(|f| !f.options.flatten).map(|f| {
        let (field, name) = (&f.ident, &f.name);
        quote!(#name => #core::fill(&mut slots.#field, #name, map))
    });
    let block_keys = fields.iter().filter(|f| f.options.flatten).map(|f| {
        let (field, ty) = (&f.ident, &f.ty);
        quote! {
            if <#ty as #core::Flatten>::take(&mut slots.#field, key, map)? {
                return ::core::result::Result::Ok(true);
            }
        }
    });
    let finishes = fields.iter().map(|f| finish_field(ident, f));
    quote! {
        #[doc(hidden)]
        #[derive(::core::default::Default)]
        #[allow(non_camel_case_types)]
        #vis struct #slots { #(#slot_fields),* }

        impl #core::Flatten for #ident {
            type Slots = #slots;

            const FIELDS: &'static [&'static str] = {
                const PARTS: &[&[&str]] = &[#(#parts),*];
                const ALL: [&str; ::hypercontact_core::const_concat::total_len(PARTS)] =
                    ::hypercontact_core::const_concat::concat(PARTS, "");
                &ALL
            };

            fn take<'de, A: ::hypercontact_core::__private::serde::de::MapAccess<'de>>(
                slots: &mut #slots,
                key: &str,
                map: &mut A,
            ) -> ::core::result::Result<bool, A::Error> {
                #[allow(unreachable_patterns)]
                match key {
                    #(#own_keys,)*
                    _ => {
                        #(#block_keys)*
                        ::core::result::Result::Ok(false)
                    }
                }
            }

            fn finish<E: ::hypercontact_core::__private::serde::de::Error>(
                slots: #slots,
            ) -> ::core::result::Result<Self, E> {
                ::core::result::Result::Ok(Self { #(#finishes),* })
            }
        }
    }
}

/// A field's value once every key is read: as read, else its default (an
/// `Option` without one is `None`), else the missing-field error serde gives.
fn finish_field(ident: &Ident, f: &ParamField) -> TokenStream {
    let (field, ty, name) = (&f.ident, &f.ty, &f.name);
    let core = core_path();
    if f.options.flatten {
        return quote!(#field: <#ty as #core::Flatten>::finish(slots.#field)?);
    }
    let absent = if f.options.default.is_some() {
        let default = format_ident!("__default_{}", field);
        quote!(#ident::#default())
    } else if f.is_option {
        quote!(::core::option::Option::None)
    } else {
        quote!(return ::core::result::Result::Err(E::missing_field(#name)))
    };
    quote! {
        #field: match slots.#field {
            ::core::option::Option::Some(value) => value,
            ::core::option::Option::None => #absent,
        }
    }
}

/// `Deserialize` for a struct with flattened blocks: every key to its
/// owner, an unknown key refused with the list of every key taken.
pub fn deserialize_impl(ident: &Ident) -> TokenStream {
    let core = core_path();
    let serde = quote!(::hypercontact_core::__private::serde);
    let expecting = format!("struct {ident}");
    let name = ident.to_string();
    quote! {
        impl<'de> #serde::Deserialize<'de> for #ident {
            fn deserialize<D: #serde::Deserializer<'de>>(
                deserializer: D,
            ) -> ::core::result::Result<Self, D::Error> {
                struct Keys;
                impl<'de> #serde::de::Visitor<'de> for Keys {
                    type Value = #ident;

                    fn expecting(&self, f: &mut ::core::fmt::Formatter) -> ::core::fmt::Result {
                        f.write_str(#expecting)
                    }

                    fn visit_map<A: #serde::de::MapAccess<'de>>(
                        self,
                        mut map: A,
                    ) -> ::core::result::Result<#ident, A::Error> {
                        let mut slots = ::core::default::Default::default();
                        let keys = #core::Key(<#ident as #core::Flatten>::FIELDS);
                        while let ::core::option::Option::Some(key) = map.next_key_seed(keys)? {
                            // Every key in FIELDS has its owner.
                            <#ident as #core::Flatten>::take(&mut slots, &key, &mut map)?;
                        }
                        <#ident as #core::Flatten>::finish(slots)
                    }
                }
                deserializer.deserialize_struct(
                    #name,
                    <#ident as #core::Flatten>::FIELDS,
                    Keys,
                )
            }
        }
    }
}
