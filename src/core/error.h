// The error types of what the program refuses (docs/design.md, invariant 6). InputError is bad
// input: it carries the file and the place in it (line:column, a JSON pointer, or an OBJ line),
// or the option, and the program turns it into one message on stderr and exit code 2.
// ResourceError is a resource limit (memory, disk) that the input would exceed: its "file" is
// the option to change, and the program exits with code 3. Code that detects either throws,
// never aborts, and throws before allocating what would not fit.
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

// A resource limit: `option` names what to change (e.g. "--beam-memory"), the message says how
// much was needed and how much there is. An InputError too, so callers that only refuse need not
// tell them apart; the command line exits with 3 for it, 2 for other input errors.
class ResourceError : public InputError {
 public:
  ResourceError(std::string option, const std::string& what) : InputError(std::move(option), "", what) {}
};

}  // namespace rayes
