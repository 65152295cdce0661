//! `#[params]`: one declaration per parameter, everything else generated.

use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use syn::{
    Expr, ExprRange, Fields, Ident, ItemStruct, LitStr, RangeLimits, Type, parse_quote,
    spanned::Spanned,
};

use crate::docs::doc_text;
use crate::flatten;

/// What `#[param(...)]` says about one field.
#[derive(Default)]
pub struct FieldOptions {
    pub default: Option<Expr>,
    unit: Option<LitStr>,
    range: Option<ExprRange>,
    positive: bool,
    check: Option<Expr>,
    rename: Option<LitStr>,
    /// The field is a parameter block whose keys stand at this level.
    pub flatten: bool,
}

pub struct ParamField {
    pub ident: Ident,
    pub ty: Type,
    /// The name in YAML (after `rename`).
    pub name: String,
    doc: String,
    pub is_option: bool,
    pub options: FieldOptions,
}

pub fn expand(args: TokenStream, item: TokenStream) -> syn::Result<TokenStream> {
    let mut item: ItemStruct = syn::parse2(item)?;
    let struct_check = parse_struct_args(args)?;
    if !item.generics.params.is_empty() {
        return Err(syn::Error::new(
            item.generics.span(),
            "#[params] structs cannot be generic",
        ));
    }
    let ident = item.ident.clone();
    let fields = take_fields(&mut item)?;
    let flattened = fields.iter().any(|f| f.options.flatten);
    add_serde_attributes(&mut item, flattened);

    let defaults = default_fns(&ident, &fields);
    let default_impl = default_impl(&ident, &fields);
    let value_impl = param_value_impl(&ident, &fields, struct_check);
    let specs = fields.iter().map(|f| spec(&ident, f));
    let flatten = flatten::flatten_impl(&ident, &item.vis, &fields);
    let deserialize = flattened.then(|| flatten::deserialize_impl(&ident));

    Ok(quote! {
        #item

        #defaults

        #default_impl

        #value_impl

        #flatten

        #deserialize

        impl ::hypercontact_core::Params for #ident {
            fn spec() -> ::std::vec::Vec<::hypercontact_core::ParamSpec> {
                let mut specs = ::std::vec::Vec::new();
                #(#specs)*
                specs
            }
        }
    })
}

/// The fields with their `#[param]` options taken off (and serde's
/// attributes for defaults and renames put on).
fn take_fields(item: &mut ItemStruct) -> syn::Result<Vec<ParamField>> {
    let ident = item.ident.clone();
    let Fields::Named(named) = &mut item.fields else {
        return Err(syn::Error::new(
            item.span(),
            "#[params] needs a struct with named fields",
        ));
    };
    let mut fields = Vec::new();
    for field in named.named.iter_mut() {
        let options = take_field_options(&mut field.attrs)?;
        let field_ident = field.ident.clone().expect("named fields have names");
        let name = options
            .rename
            .as_ref()
            .map_or_else(|| field_ident.to_string(), LitStr::value);
        let is_option = is_option(&field.ty);
        if options.flatten {
            field.attrs.push(parse_quote!(#[serde(flatten)]));
        } else if options.default.is_some() {
            let path = format!("{ident}::__default_{field_ident}");
            field.attrs.push(parse_quote!(#[serde(default = #path)]));
        } else if is_option {
            field.attrs.push(parse_quote!(#[serde(default)]));
        }
        if let Some(rename) = &options.rename {
            field.attrs.push(parse_quote!(#[serde(rename = #rename)]));
        }
        fields.push(ParamField {
            ident: field_ident,
            ty: field.ty.clone(),
            name,
            doc: doc_text(&field.attrs),
            is_option,
            options,
        });
    }
    Ok(fields)
}

/// serde's derives: both for a plain struct (unknown keys refused); only
/// `Serialize` for one with flattened blocks, whose `Deserialize` is
/// generated here ([`flatten::deserialize_impl`]).
fn add_serde_attributes(item: &mut ItemStruct, flattened: bool) {
    if flattened {
        item.attrs.push(parse_quote!(
            #[derive(
                ::core::clone::Clone,
                ::core::fmt::Debug,
                ::core::cmp::PartialEq,
                ::hypercontact_core::__private::serde::Serialize
            )]
        ));
        item.attrs.push(parse_quote!(
            #[serde(crate = "::hypercontact_core::__private::serde")]
        ));
    } else {
        item.attrs.push(parse_quote!(
            #[derive(
                ::core::clone::Clone,
                ::core::fmt::Debug,
                ::core::cmp::PartialEq,
                ::hypercontact_core::__private::serde::Serialize,
                ::hypercontact_core::__private::serde::Deserialize
            )]
        ));
        item.attrs.push(parse_quote!(
            #[serde(deny_unknown_fields, crate = "::hypercontact_core::__private::serde")]
        ));
    }
}

/// `ParamValue`: the type's description, its checks and its input paths.
/// A flattened block is checked and walked at this struct's own prefix.
fn param_value_impl(
    ident: &Ident,
    fields: &[ParamField],
    struct_check: Option<Expr>,
) -> TokenStream {
    let checks = fields.iter().map(check);
    let visits = fields.iter().map(|f| {
        let field = &f.ident;
        let name = &f.name;
        let path = if f.options.flatten {
            quote!(prefix)
        } else {
            quote!(&::hypercontact_core::param::join(prefix, #name))
        };
        quote! {
            ::hypercontact_core::ParamValue::visit_paths(&mut self.#field, #path, visit);
        }
    });
    let struct_check = struct_check.map(|check| {
        quote! {
            let checked: ::core::result::Result<(), ::hypercontact_core::ParamError> =
                (#check)(self);
            checked.map_err(|e| e.under(prefix))?;
        }
    });
    quote! {
        impl ::hypercontact_core::ParamValue for #ident {
            fn type_doc() -> ::hypercontact_core::param::TypeDoc {
                ::hypercontact_core::param::TypeDoc::Struct(
                    <Self as ::hypercontact_core::Params>::spec(),
                )
            }

            fn validate_at(
                &self,
                prefix: &str,
            ) -> ::core::result::Result<(), ::hypercontact_core::ParamError> {
                #(#checks)*
                #struct_check
                ::core::result::Result::Ok(())
            }

            fn visit_paths(
                &mut self,
                prefix: &str,
                visit: &mut dyn ::core::ops::FnMut(&str, &mut ::hypercontact_core::InputPath),
            ) {
                #(#visits)*
            }
        }
    }
}

fn parse_struct_args(args: TokenStream) -> syn::Result<Option<Expr>> {
    let mut check = None;
    if args.is_empty() {
        return Ok(None);
    }
    let parser = syn::meta::parser(|meta| {
        if meta.path.is_ident("check") {
            check = Some(meta.value()?.parse::<Expr>()?);
            Ok(())
        } else {
            Err(meta.error("unknown #[params] option (expected `check = path`)"))
        }
    });
    syn::parse::Parser::parse2(parser, args)?;
    Ok(check)
}

fn take_field_options(attrs: &mut Vec<syn::Attribute>) -> syn::Result<FieldOptions> {
    let mut options = FieldOptions::default();
    let mut kept = Vec::new();
    for attr in attrs.drain(..) {
        if !attr.path().is_ident("param") {
            kept.push(attr);
            continue;
        }
        attr.parse_nested_meta(|meta| {
            let key = meta
                .path
                .get_ident()
                .map(Ident::to_string)
                .unwrap_or_default();
            match key.as_str() {
                "default" => options.default = Some(meta.value()?.parse()?),
                "unit" => options.unit = Some(meta.value()?.parse()?),
                "range" => {
                    let expr: Expr = meta.value()?.parse()?;
                    let Expr::Range(range) = expr else {
                        return Err(meta.error("`range` takes a range, e.g. 0.0..=0.5 or 1.."));
                    };
                    options.range = Some(range);
                }
                "positive" => options.positive = true,
                "check" => options.check = Some(meta.value()?.parse()?),
                "rename" => options.rename = Some(meta.value()?.parse()?),
                "flatten" => options.flatten = true,
                _ => {
                    return Err(meta.error(
                        "unknown #[param] option (expected default, unit, range, positive, \
                         check, rename or flatten)",
                    ));
                }
            }
            Ok(())
        })?;
    }
    *attrs = kept;
    let described = options.default.is_some()
        || options.unit.is_some()
        || options.range.is_some()
        || options.positive
        || options.check.is_some()
        || options.rename.is_some();
    if options.flatten && described {
        return Err(syn::Error::new(
            proc_macro2::Span::call_site(),
            "a flattened parameter block declares its own defaults, units, ranges and names",
        ));
    }
    if options.positive && options.range.as_ref().is_some_and(|r| r.start.is_some()) {
        return Err(syn::Error::new(
            proc_macro2::Span::call_site(),
            "`positive` sets the lower bound; with it, `range` may give only an upper one \
             (`positive, range = ..=1.0`)",
        ));
    }
    Ok(options)
}

fn is_option(ty: &Type) -> bool {
    match ty {
        Type::Path(p) => p.path.segments.last().is_some_and(|s| s.ident == "Option"),
        _ => false,
    }
}

fn default_fn_ident(field: &Ident) -> Ident {
    format_ident!("__default_{}", field)
}

/// One function per declared default: serde calls it for an absent key, the
/// spec serialises it, `Default` builds from it.
fn default_fns(ident: &Ident, fields: &[ParamField]) -> TokenStream {
    let fns = fields.iter().filter_map(|f| {
        let default = f.options.default.as_ref()?;
        let name = default_fn_ident(&f.ident);
        let ty = &f.ty;
        Some(quote! {
            #[doc(hidden)]
            fn #name() -> #ty {
                #default
            }
        })
    });
    quote! {
        impl #ident {
            #(#fns)*
        }
    }
}

/// `Default` exists exactly when no parameter is required.
fn default_impl(ident: &Ident, fields: &[ParamField]) -> TokenStream {
    if fields
        .iter()
        .any(|f| f.options.default.is_none() && !f.is_option && !f.options.flatten)
    {
        return TokenStream::new();
    }
    let inits = fields.iter().map(|f| {
        let field = &f.ident;
        if f.options.flatten {
            quote!(#field: ::core::default::Default::default())
        } else if f.options.default.is_some() {
            let name = default_fn_ident(field);
            quote!(#field: #ident::#name())
        } else {
            quote!(#field: ::core::option::Option::None)
        }
    });
    quote! {
        impl ::core::default::Default for #ident {
            fn default() -> Self {
                Self { #(#inits),* }
            }
        }
    }
}

/// The range as a `ParamRange` expression, if the field has one. `positive`
/// is the lower bound `> 0`; a `range` beside it gives the upper bound.
fn range_expr(options: &FieldOptions) -> Option<TokenStream> {
    let bound = |e: &Option<Box<Expr>>, inclusive: bool| match e {
        None => quote!(::core::ops::Bound::Unbounded),
        Some(e) if inclusive => quote!(::core::ops::Bound::Included((#e) as f64)),
        Some(e) => quote!(::core::ops::Bound::Excluded((#e) as f64)),
    };
    let Some(range) = options.range.as_ref() else {
        return options
            .positive
            .then(|| quote! { ::hypercontact_core::param::ParamRange::POSITIVE });
    };
    let lo = if options.positive {
        quote!(::core::ops::Bound::Excluded(0.0))
    } else {
        bound(&range.start, true)
    };
    let hi = bound(&range.end, matches!(range.limits, RangeLimits::Closed(_)));
    Some(quote! { ::hypercontact_core::param::ParamRange { lo: #lo, hi: #hi } })
}

/// The statement adding the field's spec (a flattened block's specs, in
/// their order) to `specs`.
fn spec(ident: &Ident, f: &ParamField) -> TokenStream {
    let name = &f.name;
    let doc = &f.doc;
    let ty = &f.ty;
    if f.options.flatten {
        return quote! {
            specs.extend(<#ty as ::hypercontact_core::Params>::spec());
        };
    }
    let unit = f
        .options
        .unit
        .as_ref()
        .map_or_else(String::new, LitStr::value);
    let default = match &f.options.default {
        Some(_) => {
            let fn_name = default_fn_ident(&f.ident);
            quote! {
                ::core::option::Option::Some(
                    ::hypercontact_core::__private::serde_json::to_value(&#ident::#fn_name())
                        .expect("a parameter default serialises to JSON"),
                )
            }
        }
        None => quote!(::core::option::Option::None),
    };
    let required = f.options.default.is_none() && !f.is_option;
    let range = match range_expr(&f.options) {
        Some(r) => quote!(::core::option::Option::Some(#r)),
        None => quote!(::core::option::Option::None),
    };
    let custom = f.options.check.is_some();
    quote! {
        specs.push(::hypercontact_core::ParamSpec {
            name: #name,
            unit: #unit,
            doc: #doc,
            ty: <#ty as ::hypercontact_core::ParamValue>::type_doc(),
            default: #default,
            required: #required,
            range: #range,
            custom_check: #custom,
        });
    }
}

fn check(f: &ParamField) -> TokenStream {
    let field = &f.ident;
    let name = &f.name;
    if f.options.flatten {
        return quote! {
            ::hypercontact_core::ParamValue::validate_at(&self.#field, prefix)?;
        };
    }
    let range = range_expr(&f.options).map(|range| {
        quote! {
            ::hypercontact_core::param::check_range(&path, &self.#field, &#range)?;
        }
    });
    let custom = f.options.check.as_ref().map(|check| {
        quote! {
            let checked: ::core::result::Result<(), ::std::string::String> =
                (#check)(&self.#field);
            checked.map_err(|message| ::hypercontact_core::ParamError::new(&path, message))?;
        }
    });
    quote! {
        {
            let path = ::hypercontact_core::param::join(prefix, #name);
            #range
            #custom
            ::hypercontact_core::ParamValue::validate_at(&self.#field, &path)?;
        }
    }
}
