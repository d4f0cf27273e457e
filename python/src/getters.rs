//! `class_methods!`: a class's Python methods with its read-only attributes written one a
//! line, each an expression of the object (`self`) and the interpreter (`py`).

/// The `#[pymethods]` of `$class`: a getter per `name: Type = |object, py| expression;`
/// (with its doc comment), then the methods written out in `methods { ... }`.
macro_rules! class_methods {
    (
        $class:ty {
            $($(#[$doc:meta])* $name:ident: $ty:ty = |$object:ident, $py:ident| $value:expr;)*
        }
        methods { $($methods:tt)* }
    ) => {
        #[pymethods]
        impl $class {
            $(
                $(#[$doc])*
                #[getter]
                #[allow(unused_variables)]
                fn $name<'py>(&self, $py: Python<'py>) -> $ty {
                    let $object = self;
                    $value
                }
            )*
            $($methods)*
        }
    };
}
pub(crate) use class_methods;
