#pragma once
/// @file error.hpp
/// MANTA's one error hierarchy. Library code throws; the CLI catches at the top, prints one
/// line and exits with 2 (bad input: ConfigError, InputError, IoError) or 1 (failed computation:
/// ConvergenceError, NumericalError). A message quotes input text as it is given; the control
/// bytes in it are escaped when the error is made (core::printable), so no message carries a raw
/// ESC, carriage return or NUL to the terminal.

#include <stdexcept>
#include <string>

namespace manta {

/// Base of every error MANTA throws on purpose.
class Error : public std::runtime_error {
public:
    /// The message, its control bytes escaped as \xNN (core::printable).
    explicit Error(const std::string& message);
    explicit Error(const char* message);
    /// Process exit code the CLI uses for this error: 2 for bad input, 1 for a failed computation.
    [[nodiscard]] virtual int exit_code() const noexcept { return 1; }
};

/// A configuration file (YAML) is wrong: the message names file, line, key path, value,
/// expectation.
class ConfigError : public Error {
public:
    using Error::Error;
    [[nodiscard]] int exit_code() const noexcept override { return 2; }
};

/// Any other user input is wrong (command-line value, CSV content, database file).
class InputError : public Error {
public:
    using Error::Error;
    [[nodiscard]] int exit_code() const noexcept override { return 2; }
};

/// A file could not be opened, read or written.
class IoError : public Error {
public:
    using Error::Error;
    [[nodiscard]] int exit_code() const noexcept override { return 2; }
};

/// An iterative method did not converge (trim, Newton, optimiser); the message says how far it got.
class ConvergenceError : public Error {
public:
    using Error::Error;
};

/// NaN, Inf or another numerical breakdown; the message names where it appeared.
class NumericalError : public Error {
public:
    using Error::Error;
};

namespace detail {
[[noreturn]] void require_failed(const char* expr, const char* file, int line,
                                 const std::string& msg);
}  // namespace detail

}  // namespace manta

/// Cheap precondition check that stays on in release builds; throws manta::InputError.
#define MANTA_REQUIRE(cond, msg)                                                        \
    do {                                                                                \
        if (!(cond)) ::manta::detail::require_failed(#cond, __FILE__, __LINE__, (msg)); \
    } while (false)

#ifndef NDEBUG
/// Invariant check for programming errors, debug builds only.
#define MANTA_ASSERT(cond)                                                                    \
    do {                                                                                      \
        if (!(cond)) ::manta::detail::require_failed(#cond, __FILE__, __LINE__, "assertion"); \
    } while (false)
#else
#define MANTA_ASSERT(cond) ((void)0)
#endif
