#include <string>

#include "cli/commands.h"
#include "core/installed_data.h"

namespace rayverify::cli {

std::string default_corpus() { return data_file("corpus", RAYVERIFY_DEFAULT_CORPUS).string(); }

}  // namespace rayverify::cli
