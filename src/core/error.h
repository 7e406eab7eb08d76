#pragma once
// Errors inside nephele are typed exceptions (STYLE.md 6); the C API converts them to status codes.
// Messages name the file, the variable and what was expected.
#include <stdexcept>
#include <string>

namespace nph {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Bad input data: a file, variable or attribute that is not what nephele expects.
class InputError : public Error {
 public:
  using Error::Error;
};

/// A file could not be read or written.
class IoError : public Error {
 public:
  using Error::Error;
};

/// An OpenGL context, shader or call failed.
class GlError : public Error {
 public:
  using Error::Error;
};

/// A caller passed an invalid argument or used an object in the wrong state.
class UsageError : public Error {
 public:
  using Error::Error;
};

}  // namespace nph
