//! The `robot!` grammar on token streams from arbitrary text: the macro's output is always
//! items (the robot's struct and impl, or `compile_error!`s and a stub struct), never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|text: &str| {
    let Ok(tokens) = text.parse::<proc_macro2::TokenStream>() else {
        return;
    };
    let out = dynamics_gen::macro_support::robot(tokens);
    if let Err(e) = syn::parse2::<syn::File>(out.clone()) {
        panic!("robot! gave tokens that are not items ({e}):\n{out}");
    }
});
