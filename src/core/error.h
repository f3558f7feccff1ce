// The one error type for bad input (docs/design.md, invariant 6). It carries the file and the place in
// it (line:column, a JSON pointer, or an OBJ line), and the program turns it into one message
// on stderr and exit code 2. Code that detects bad input throws this, never aborts.
#pragma once
#include <stdexcept>
#include <string>

namespace rayes {

class InputError : public std::runtime_error {
 public:
  InputError(std::string file, std::string place, const std::string& what)
      : std::runtime_error(what), file_(std::move(file)), place_(std::move(place)) {}
  const std::string& file() const { return file_; }
  const std::string& place() const { return place_; }
  // "file:place: message", the form printed by the program.
  std::string message() const {
    std::string s = file_;
    if (!place_.empty()) s += ":" + place_;
    return s + ": " + what();
  }
 private:
  std::string file_, place_;
};

}  // namespace rayes
