#include "app/huge_pages.h"
#include <cstdlib>
#include <cstring>
#include <string>
#include <unistd.h>

namespace rayes {

void restartWithHugePages(char** argv) {
#if defined(__linux__) && defined(__GLIBC__)
  const char* off = std::getenv("RAYES_HUGE_PAGES");
  if (off && std::strcmp(off, "0") == 0) return;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  // Already named (by us, or by the user, whatever its value): never exec twice.
  if (tunables && std::strstr(tunables, "glibc.malloc.hugetlb")) return;
  // A copy: setenv may invalidate the string getenv returned, and a failed exec restores it.
  const bool hadTunables = tunables != nullptr;
  const std::string old = hadTunables ? tunables : "";
  const std::string value = (old.empty() ? "" : old + ":") + "glibc.malloc.hugetlb=1";
  if (setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  // The exec failed (no /proc, a sandbox): go on without huge pages, as before.
  if (hadTunables) setenv("GLIBC_TUNABLES", old.c_str(), 1);
  else unsetenv("GLIBC_TUNABLES");
#else
  (void)argv;
#endif
}

}  // namespace rayes
