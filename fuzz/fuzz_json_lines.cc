// JSON-lines table reader (import/data_table.h, ReadJsonLinesTable): the fuzzed bytes as a table
// `cellmetry import` reads, one JSON object per line, nested values flattened into columns. Deep
// nesting, numbers beyond a double, a key twice in one object must each be an InputError at
// their line, never a crash, a hang or nlohmann's own exception.
#include <string>

#include "cellmetry/import/data_table.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = cellmetry::fuzz::TempDir() + "/table.jsonl";
  cellmetry::fuzz::WriteFile(path, data, size);
  cellmetry::fuzz::CheckContract([&] {
    const cellmetry::DataTable table = cellmetry::ReadJsonLinesTable(path);
    (void)table.num_rows();
  });
  return 0;
}
