// The exit status the command that ran has chosen (commands.h).

#include "commands.h"

namespace quiver::tools {
namespace {
int g_exit = 0;
}

int exit_code() { return g_exit; }
void set_exit_code(int code) { g_exit = code; }

}  // namespace quiver::tools
