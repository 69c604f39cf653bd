//! The macro that declares a standard's function table from one list of its functions:
//! each function's pointer type, named and typed as the standard's header declares it
//! (`fmi2InstantiateTYPE`, ...), a table of them all, their C names in the table's order,
//! and the table's resolution from a loaded binary.

/// `functions! { COUNT; field TYPE "cName" (arguments) -> result; ... }`.
macro_rules! functions {
    ($count:literal; $($field:ident $ty:ident $name:literal ($($arg:ty),*) $(-> $ret:ty)?;)*) => {
        $(
            #[doc = concat!("`", $name, "`, as the standard's header declares it.")]
            pub type $ty = unsafe extern "C" fn($($arg),*) $(-> $ret)?;
        )*

        /// Every function of the standard, resolved from one binary (see [`Api`], which
        /// holds the binary loaded while its table is in use).
        #[derive(Clone, Copy)]
        pub struct Table {
            $(
                #[doc = concat!("`", $name, "`.")]
                pub $field: $ty,
            )*
        }

        /// The C names of the functions, in the order of [`Table`]'s fields (the header's).
        pub const FUNCTION_NAMES: [&str; $count] = [$($name),*];

        impl Table {
            /// Resolves every function of `library`; a missing one is an error naming it.
            fn resolve(library: &$crate::library::Library) -> Result<Table, String> {
                Ok(Table {
                    $(
                        // SAFETY: the standard's function of that name, typed as its
                        // header declares it; the `Api` holding the table holds the library.
                        $field: unsafe { library.function::<$ty>($name) }.map_err(|e| {
                            format!("{}: no {}: {e}", library.path().display(), $name)
                        })?,
                    )*
                })
            }
        }

        /// Every function of the standard, resolved from a loaded binary, for an importer
        /// that calls them as it likes (the hostile importer of `tests/robustness`: NULL
        /// pointers, wrong states). It holds the library, so the pointers stay valid as long
        /// as the `Api` lives; the table it dereferences to is `Copy`, for calls within its
        /// life.
        #[derive(Clone)]
        pub struct Api {
            table: Table,
            _library: std::sync::Arc<libloading::Library>,
        }

        impl Api {
            /// Every function of `library` (an error names the first one missing).
            pub fn load(library: &$crate::library::Library) -> Result<Api, String> {
                Ok(Api {
                    table: Table::resolve(library)?,
                    _library: library.shared(),
                })
            }
        }

        impl std::ops::Deref for Api {
            type Target = Table;
            fn deref(&self) -> &Table {
                &self.table
            }
        }
    };
}
