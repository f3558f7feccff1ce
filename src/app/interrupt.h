// Signals (SIGINT, SIGTERM, SIGHUP) and what a stopped run leaves behind. The one place that
// installs signal handlers; OutputSet and the checkpoint writer register here what a signal
// must remove.
//
// Two behaviours. By default a signal removes every registered temporary file and every
// registered folder the run created (deepest first; a folder that is not empty stays), then
// the process dies by the signal as if it were not handled. When the run can resume
// (setStopOnSignal(true): --checkpoint or --time-limit), a signal only sets a flag: the
// Renderer sees stopRequested() between generations, the run writes its checkpoint, removes
// its other outputs and exits with code 4. A second signal while it stops dies at once, with
// the cleanup (a checkpoint half-written then is a temporary: the previous one stays valid).
//
// Thread-safety: the register functions are for the main thread; the handler calls only
// async-signal-safe functions (unlink, rmdir, signal, raise) on paths kept in fixed arrays. A
// path too long for a slot, or a full table, is only not removed on a signal.
#pragma once
#include <string>

namespace rayes {

// Installs the handlers (once; a signal that is ignored, e.g. under nohup, stays ignored).
void installSignalHandlers();
// A file (a temporary) or a folder (created by this run) to remove on a deadly signal; returns
// the slot to unregister (-1: not registered).
int registerCleanupFile(const std::string& path);
int registerCleanupFolder(const std::string& path);
void unregisterCleanup(int slot);

void setStopOnSignal(bool stop);
// Whether a signal asked a resumable run to stop, and which (0: none).
bool stopRequested();
int stopSignal();

}  // namespace rayes
