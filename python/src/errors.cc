// Errors: quiver::Error values become Python exceptions whose class tells the kind (each class is
// also the matching built-in: NotFoundError is a KeyError, TypeMismatchError a TypeError, ...),
// with the C++ message and the error code's name in `.code`.

#include <pybind11/eval.h>

#include "common.h"

namespace quiver::python {
namespace {

constexpr const char* kExceptions = R"py(
class Error(RuntimeError):
    """A Quiver error: `code` names the kind ("not_found", "refused", ...)."""
    def __init__(self, message, code="internal"):
        super().__init__(message)
        self.code = code
    def __str__(self):
        return str(self.args[0]) if self.args else ""

class NotFoundError(Error, KeyError):
    """A node, edge, attribute, frame or file does not exist."""

class TypeMismatchError(Error, TypeError):
    """A typed read found a value of another type."""

class InvalidArgumentError(Error, ValueError):
    """An argument the function cannot accept (bad name, size, format, a name already taken)."""

class RefusedError(Error):
    """A grammar rule or a lock refused the change."""

class TimeoutError(Error):
    """A bounded wait ended before its condition held."""

class WrongThreadError(Error):
    """An agent's graph was used off the agent's thread (use Agent.call)."""
)py";

PyObject* g_classes[6] = {};  // Error, NotFound, TypeMismatch, InvalidArgument, Refused, Timeout

}  // namespace

void raise(const Error& e) {
  PyObject* cls = g_classes[0];
  switch (e.code) {
    case ErrorCode::kNotFound: cls = g_classes[1]; break;
    case ErrorCode::kTypeMismatch: cls = g_classes[2]; break;
    case ErrorCode::kInvalidArgument:
    case ErrorCode::kAlreadyExists:
    case ErrorCode::kMalformed:
    case ErrorCode::kTruncated:
    case ErrorCode::kTooLarge:
    case ErrorCode::kUnsupportedVersion: cls = g_classes[3]; break;
    case ErrorCode::kRefused: cls = g_classes[4]; break;
    case ErrorCode::kTimeout: cls = g_classes[5]; break;
    default: break;
  }
  py::object instance = py::reinterpret_borrow<py::object>(cls)(e.message, to_string(e.code));
  PyErr_SetObject(cls, instance.ptr());
  throw py::error_already_set();
}

void bind_errors(py::module_& m) {
  py::exec(kExceptions, m.attr("__dict__"));
  const char* names[6] = {"Error", "NotFoundError", "TypeMismatchError", "InvalidArgumentError", "RefusedError",
                          "TimeoutError"};
  for (int i = 0; i < 6; ++i) g_classes[i] = py::object(m.attr(names[i])).release().ptr();
}

}  // namespace quiver::python
