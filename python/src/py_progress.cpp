#include "py_progress.h"

#include "lodforge/error.h"

#include <cmath>

namespace py = pybind11;

namespace lodforge::python {

CallbackProgress::~CallbackProgress() {
    // error_already_set holds Python references: drop them with the GIL (the destructor may run while
    // the work's exception unwinds, after the GIL came back, which is the only place this is destroyed).
    error_.reset();
}

void CallbackProgress::report(double fraction, std::string_view stage) {
    if (cancelled()) return;
    {
        // Every stage change, then every 1 % at most.
        std::lock_guard lock(mutex_);
        const bool new_stage = stage != last_stage_;
        if (!new_stage && std::fabs(fraction - last_fraction_) < 0.01 && fraction < 1.0) return;
        last_fraction_ = fraction;
        if (new_stage) last_stage_ = std::string(stage);
    }
    py::gil_scoped_acquire gil;
    if (cancelled()) return;  // another thread's call may have cancelled while this one waited
    try {
        const py::object answer = callback_(fraction, py::str(std::string(stage)));
        if (!answer.is_none() && !answer.cast<bool>()) cancelled_.store(true, std::memory_order_relaxed);
    } catch (py::error_already_set& e) {
        error_.emplace(std::move(e));
        cancelled_.store(true, std::memory_order_relaxed);
    } catch (const py::cast_error&) {
        cancelled_.store(true, std::memory_order_relaxed);
    }
}

void CallbackProgress::rethrow_callback_error() {
    if (error_) {
        py::error_already_set e = std::move(*error_);
        error_.reset();
        throw e;
    }
}

void bind_errors(py::module_& m) {
    static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
    error.doc() = "An error of the LodForge core: str(e) is its message (naming the file), e.kind one of "
                  "'io', 'format', 'invalid', 'unsupported', 'argument', 'cancelled'.";
    static py::exception<Error> cancelled(m, "Cancelled", error.ptr());
    // Shown as lodforge.Error in tracebacks: the package is the public name.
    error.attr("__module__") = "lodforge";
    cancelled.attr("__module__") = "lodforge";
    cancelled.doc() = "The work was cancelled (the progress callback returned False).";
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const Error& e) {
            const py::object& cls = e.kind() == Error::Kind::cancelled ? cancelled : error;
            py::object instance = cls(e.what());
            instance.attr("kind") = kind_name(e.kind());
            PyErr_SetObject(cls.ptr(), instance.ptr());
        }
    });
}

}  // namespace lodforge::python
