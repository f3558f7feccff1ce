// All-or-nothing outputs. Every file a run produces (EXR, PNG preview, stats, report) is
// written to a temporary name in its target's folder; only when all of them have been written
// are they renamed onto their targets. On any failure -- while writing, or a rename -- no
// output of the run is left behind: temporaries are removed, and targets already renamed in
// this commit are removed too, and so are folders created for them; a run stopped by SIGINT,
// SIGTERM or SIGHUP removes its temporaries and the folders it created before it dies
// (app/interrupt.h). The one place in the program that writes output files (besides the
// checkpoint, which is written atomically on its own: app/checkpoint.h).
//
// Failures are InputError naming the target with the system's reason (errno is read before
// any cleanup can overwrite it): an unwritable output is bad input, exit code 2.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace rayes {

class OutputSet {
 public:
  OutputSet() = default;
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;
  // Removes the temporaries (and the folders it created) of a set that was never committed.
  ~OutputSet();

  // Claims `target` (what: "image", "stats", ...): it must not be a directory, a device or a
  // pipe, nor claimed twice; its folder is created, and the temporary is created at once, so
  // that an unwritable place fails before the render rather than after it.
  // A target that is the same file as an input named by addInput is refused ("the <what>
  // would overwrite an input of this run").
  void add(const std::string& target, const std::string& what);
  // Names a file this run reads (the scene, a reference, a mask); empty names are ignored.
  // Call before the add() of the targets it must protect.
  void addInput(const std::string& path) {
    if (!path.empty()) inputs_.push_back(path);
  }
  // Fills the temporary of a claimed target: `write` gets the temporary's path and may throw
  // (any std::exception becomes an InputError naming the target).
  void write(const std::string& target, const std::function<void(const std::string& temporary)>& write);
  void writeText(const std::string& target, const std::string& text);
  // Renames every temporary onto its target.
  void commit();

 private:
  struct Entry {
    std::string target, temporary, what;
    int signalSlot;  // where the signal handler finds the temporary (-1: not registered)
  };
  const Entry& entry(const std::string& target) const;
  void removeTemporaries();
  std::vector<Entry> entries_;
  std::vector<std::string> inputs_;
  std::vector<std::string> createdFolders_;  // outermost first
  std::vector<int> folderSlots_;             // their slots in the signal handler's table (app/interrupt.h)
  bool committed_ = false;
};

}  // namespace rayes
