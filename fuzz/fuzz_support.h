// What every harness in fuzz/ shares: a private temporary folder, writing the fuzzed bytes into a
// file, and the contract itself.
//
// The contract: any input either loads or raises cellmetry::InputError (the clean error the command
// line prints as FILE:LINE:COLUMN and exits 2 on). Any other exception is a finding: CheckContract
// prints its type and message and aborts, so that libFuzzer keeps the input as a crash. Sanitizer
// reports and hangs (libFuzzer's -timeout) are findings too.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace cellmetry::fuzz {

// A folder of this process's own under $TMPDIR (made once, removed at exit).
const std::string& TempDir();
void WriteFile(const std::string& path, const std::uint8_t* data, std::size_t size);
void WriteFile(const std::string& path, const std::string& text);
void CopyFile(const std::string& from, const std::string& to);
// The first `lines` lines of a text file (a template small enough to parse thousands of times a
// second).
std::string HeadLines(const std::string& path, int lines);

// Runs `load`; returns true when it loaded, false on InputError; aborts on anything else.
template <typename F>
bool CheckContract(F&& load);

// Prints what broke the contract and its detail, then aborts (libFuzzer keeps the input).
[[noreturn]] void Violation(const std::string& what, const std::string& detail);

}  // namespace cellmetry::fuzz

#include <exception>
#include <typeinfo>

#include "cellmetry/basics/error.h"

template <typename F>
bool cellmetry::fuzz::CheckContract(F&& load) {
  try {
    load();
    return true;
  } catch (const cellmetry::InputError&) {
    return false;
  } catch (const std::exception& e) {
    Violation(std::string("an exception other than InputError escaped: ") + typeid(e).name(),
              e.what());
  } catch (...) {
    Violation("an exception other than InputError escaped", "(not a std::exception)");
  }
}
