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

/// A value of the crate's result as its Python class holds it: a vector handed to numpy as
/// an array without a copy, any other value as it is.
pub trait IntoField<Field> {
    /// The field of this value.
    fn into_field(self, py: pyo3::Python<'_>) -> Field;
}

impl<T> IntoField<T> for T {
    fn into_field(self, _: pyo3::Python<'_>) -> T {
        self
    }
}

impl<T: numpy::Element> IntoField<crate::arrays::Column<T>> for Vec<T> {
    fn into_field(self, py: pyo3::Python<'_>) -> crate::arrays::Column<T> {
        crate::arrays::array(py, self)
    }
}

impl<T: numpy::Element> IntoField<Option<crate::arrays::Column<T>>> for Option<Vec<T>> {
    fn into_field(self, py: pyo3::Python<'_>) -> Option<crate::arrays::Column<T>> {
        self.map(|v| crate::arrays::array(py, v))
    }
}

/// The frozen class `$class` (Python `$name`) of a result: its fields, read-only
/// attributes, each written once with its type and its value taken of the crate's result
/// (`|py, pattern: Source|`, [`IntoField`]) in `of`, which builds the class; `private` fields
/// are no attributes; `len` the column whose length is the class's `len()`, `repr` its `repr()`, then any methods written
/// out. Attributes before the class name (`#[derive(Clone)]`) go to its struct.
macro_rules! result_class {
    (
        $(#[$doc:meta])*
        $class:ident = $name:literal of |$py:ident, $source:tt: $source_ty:ty| {
            $($(#[$fdoc:meta])* $field:ident: $ty:ty = $value:expr,)*
        }
        $(private { $($(#[$pdoc:meta])* $private:ident: $pty:ty = $pvalue:expr,)* })?
        $(len $len:ident;)?
        $(repr |$this:ident| $repr:expr;)?
        $(methods { $($methods:tt)* })?
    ) => {
        $(#[$doc])*
        #[pyclass(name = $name, module = "angletrack", frozen)]
        #[derive(Debug)]
        pub struct $class {
            $($(#[$fdoc])* #[pyo3(get)] pub(crate) $field: $ty,)*
            $($($(#[$pdoc])* $private: $pty,)*)?
        }

        impl $class {
            /// The class of the crate's result.
            #[allow(clippy::unnecessary_wraps, unused_variables)]
            pub(crate) fn of($py: Python<'_>, $source: $source_ty) -> $crate::errors::Result<Self> {
                use $crate::getters::IntoField;
                // The private fields first: they may borrow what the attributes take.
                Ok(Self { $($($private: $pvalue,)*)? $($field: $value.into_field($py),)* })
            }
        }

        #[pymethods]
        impl $class {
            $(
                fn __len__(&self, py: Python<'_>) -> usize {
                    numpy::PyUntypedArrayMethods::len(self.$len.bind(py))
                }
            )?
            $(
                fn __repr__(&self) -> String {
                    let $this = self;
                    $repr
                }
            )?
            $($($methods)*)?
        }
    };
}
pub(crate) use result_class;
