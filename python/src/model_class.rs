//! `model_class!`: a frozen Python class mirroring a model struct of the std crate field by
//! field (`SensorModel`, `ResolverModel`): each field a keyword argument defaulting to the
//! crate's `Default`, an attribute, and the `repr`'s `name=value`.

use angletrack::MAX_ANGLE_ERROR_HARMONICS;

use crate::arrays::Count;
use crate::errors::{Error, Result};

/// A field of a model as its Python class holds it.
pub trait ModelField: Sized {
    /// What the caller gives.
    type Argument;
    /// The crate's field.
    type Model;
    /// The field of the argument `given` of `parameter` (refused naming it).
    fn given(given: Self::Argument, parameter: &'static str) -> Result<Self>;
    /// The field of the crate's value (its default).
    fn of_model(model: Self::Model) -> Self;
    /// The crate's field.
    fn to_model(&self) -> Self::Model;
}

impl ModelField for f64 {
    type Argument = f64;
    type Model = f64;
    fn given(given: f64, _: &'static str) -> Result<Self> {
        Ok(given)
    }
    fn of_model(model: f64) -> Self {
        model
    }
    fn to_model(&self) -> f64 {
        *self
    }
}

/// Whole-number fields: given as any Python integer, refused beyond the type's range.
macro_rules! whole_fields {
    ($($t:ty),*) => {$(
        impl ModelField for $t {
            type Argument = Count;
            type Model = $t;
            fn given(given: Count, parameter: &'static str) -> Result<Self> {
                given.get(parameter)
            }
            fn of_model(model: $t) -> Self {
                model
            }
            fn to_model(&self) -> $t {
                *self
            }
        }
    )*};
}
whole_fields!(u32, usize);

/// The sensor model's angle error harmonics `(order, amplitude rad, phase rad)`: a list of
/// at most [`MAX_ANGLE_ERROR_HARMONICS`], the crate's fixed table with unused entries 0.
impl ModelField for Vec<(u32, f64, f64)> {
    type Argument = Vec<(u32, f64, f64)>;
    type Model = [(u32, f64, f64); MAX_ANGLE_ERROR_HARMONICS];
    fn given(given: Self, parameter: &'static str) -> Result<Self> {
        if given.len() > MAX_ANGLE_ERROR_HARMONICS {
            return Err(Error::value(
                parameter,
                format!(
                    "holds {} harmonics, at most {MAX_ANGLE_ERROR_HARMONICS} are supported",
                    given.len()
                ),
            ));
        }
        Ok(given)
    }
    fn of_model(model: Self::Model) -> Self {
        model.into_iter().filter(|&h| h != (0, 0.0, 0.0)).collect()
    }
    fn to_model(&self) -> Self::Model {
        let mut table = [(0, 0.0, 0.0); MAX_ANGLE_ERROR_HARMONICS];
        for (slot, &harmonic) in table.iter_mut().zip(self) {
            *slot = harmonic;
        }
        table
    }
}

/// The class `$class` (Python `$name`) of the model `$model`'s fields (each a
/// [`ModelField`]), with `model()`, a constructor of keyword arguments (`None`: the
/// crate's default), a `repr` of them all, and the `methods` written out.
macro_rules! model_class {
    (
        $(#[$doc:meta])*
        $class:ident = $name:literal of $model:ident {
            $($(#[$fdoc:meta])* $field:ident: $ty:ty,)*
        }
        methods { $($methods:tt)* }
    ) => {
        $(#[$doc])*
        #[pyclass(name = $name, module = "angletrack", frozen, get_all)]
        #[derive(Debug, Clone)]
        pub struct $class {
            $($(#[$fdoc])* $field: $ty,)*
        }

        impl $class {
            /// The crate's model.
            pub(crate) fn model(&self) -> $model {
                $model { $($field: ModelField::to_model(&self.$field),)* }
            }
        }

        #[pymethods]
        impl $class {
            #[new]
            #[pyo3(signature = (*, $($field = None),*))]
            #[allow(clippy::too_many_arguments)]
            fn py_new($($field: Option<<$ty as ModelField>::Argument>),*) -> Result<Self> {
                let d = $model::default();
                Ok(Self {
                    $($field: match $field {
                        Some(given) => ModelField::given(given, stringify!($field))?,
                        None => <$ty as ModelField>::of_model(d.$field),
                    },)*
                })
            }

            fn __repr__(&self) -> String {
                let fields = [$(format!("{}={:?}", stringify!($field), self.$field)),*];
                format!("{}({})", $name, fields.join(", "))
            }

            $($methods)*
        }
    };
}
pub(crate) use model_class;
