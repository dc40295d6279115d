// ReadCsvTable (data_table.h): a spreadsheet's CSV export as it comes — a byte-order mark or
// none, ',' ';' or tab between fields, quoted fields with separators, doubled quotes and line
// breaks inside, a decimal comma, an 8-bit encoding the mapping names.
#include <algorithm>
#include <cstdio>
#include <map>

#include "cellmetry/basics/utf8.h"
#include "cellmetry/formats/input_file.h"
#include "cellmetry/import/data_table.h"

namespace cellmetry {
namespace {

struct Field {
  std::string text;
  int position = 0;  // 1-based field number in its record
};

struct Record {
  std::vector<Field> fields;
  int line = 0;  // where the record starts
};

std::string Trim(const std::string& s) {
  const size_t begin = s.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  return s.substr(begin, s.find_last_not_of(" \t") - begin + 1);
}

std::string SeparatorName(char c) { return c == '\t' ? "tab" : std::string("'") + c + "'"; }

// The separator the header line holds most of outside quotes (',' when it holds none).
char DetectSeparator(const std::string& text, char decimal) {
  std::map<char, int> counts = {{',', 0}, {';', 0}, {'\t', 0}};
  bool quoted = false;
  for (char c : text) {
    if (c == '\n') break;
    if (c == '"') quoted = !quoted;
    if (!quoted && counts.count(c)) ++counts[c];
  }
  if (decimal == ',') counts.erase(',');
  char best = decimal == ',' ? ';' : ',';
  int most = 0;
  for (const auto& [c, n] : counts) {
    if (n > most) {
      most = n;
      best = c;
    }
  }
  return best;
}

std::vector<Record> SplitRecords(const std::string& path, const std::string& text, char separator) {
  std::vector<Record> records;
  Record record;
  std::string field;
  bool quoted = false;      // inside a quoted field
  bool was_quoted = false;  // this field was quoted (its spaces are its own)
  int line = 1;
  int quote_line = 0;
  record.line = 1;
  auto end_field = [&] {
    record.fields.push_back(
        {was_quoted ? field : Trim(field), static_cast<int>(record.fields.size()) + 1});
    field.clear();
    was_quoted = false;
  };
  auto end_record = [&] {
    end_field();
    const bool blank = record.fields.size() == 1 && record.fields[0].text.empty();
    if (!blank) records.push_back(std::move(record));
    record = Record();
    record.line = line;
  };
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"') {
        if (i + 1 < text.size() && text[i + 1] == '"') {
          field += '"';
          ++i;
        } else {
          quoted = false;
        }
      } else {
        if (c == '\n') ++line;
        if (c != '\r') field += c;
      }
      continue;
    }
    if (c == '"' && Trim(field).empty()) {
      quoted = true;
      was_quoted = true;
      quote_line = line;
      field.clear();
    } else if (c == separator) {
      end_field();
    } else if (c == '\n') {
      ++line;
      end_record();
    } else if (c != '\r') {
      field += c;
    }
  }
  if (quoted) {
    throw InputError({path, quote_line, static_cast<int>(record.fields.size()) + 1},
                     "a quoted field is never closed",
                     "Close the quote; a quote inside a quoted field is written twice (\"\")");
  }
  end_record();
  return records;
}

// Refuses the first field holding bytes that are not UTF-8 (a file in an 8-bit encoding the
// mapping did not name), naming the byte and what comes before it in the field.
void ExpectUtf8(const std::string& path, const std::vector<Record>& records) {
  for (const auto& record : records) {
    for (const auto& field : record.fields) {
      const std::optional<size_t> bad = FirstInvalidUtf8Byte(field.text);
      if (!bad) continue;
      char byte[8];
      std::snprintf(byte, sizeof(byte), "0x%02X", static_cast<unsigned char>(field.text[*bad]));
      const size_t shown = std::min<size_t>(*bad, 24);  // of the field's text before the byte
      const std::string before = field.text.substr(*bad - shown, shown);
      throw InputError({path, record.line, field.position},
                       std::string("the byte ") + byte + " in field " +
                           std::to_string(field.position) +
                           (before.empty() ? "" : " (after '" + before + "')") +
                           " is not UTF-8: the table is in an 8-bit encoding",
                       "Say which in the mapping: encoding: latin1 beside the table's path "
                       "(table: {path: ..., encoding: latin1}, or so under tables:; "
                       "windows-1252 and cp1252 read the same), or save the table as UTF-8");
    }
  }
}

// The table file's text as UTF-8, its byte-order mark dropped; UTF-16 refused.
std::string ReadCsvText(const std::string& path, TextEncoding encoding) {
  std::string text = ReadRegularFile(
      path, kMaxTableBytes, "Check 'table:' in the mapping (a path relative to the mapping file)");
  if (text.rfind("\xFF\xFE", 0) == 0 || text.rfind("\xFE\xFF", 0) == 0) {
    throw InputError({path, 1, 0}, "the table is UTF-16 text",
                     "Save it as CSV UTF-8 (in a spreadsheet: 'CSV UTF-8 (comma delimited)')");
  }
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);  // UTF-8 byte-order mark
  // One byte is one character in an 8-bit encoding: lines and fields stay where they were.
  if (encoding == TextEncoding::kWindows1252) text = Windows1252ToUtf8(text);
  return text;
}

// The dialect's separator, or the one the text's first lines use; never the decimal mark.
char SeparatorOf(const std::string& path, const std::string& text, const CsvDialect& dialect) {
  if (dialect.decimal != '.' && dialect.decimal != ',') {
    throw InputError({path, 0, 0}, "decimal mark must be '.' or ','");
  }
  const char separator =
      dialect.separator ? dialect.separator : DetectSeparator(text, dialect.decimal);
  if (separator == dialect.decimal) {
    throw InputError({path, 1, 0},
                     "the separator and the decimal mark are both " + SeparatorName(separator),
                     "A table with decimal commas separates its fields with ';' or tabs");
  }
  return separator;
}

// The header's names as the table's columns; a name given twice is refused.
void AddHeader(const std::string& path, const Record& header, DataTable* table) {
  std::map<std::string, int> seen;
  for (const auto& field : header.fields) {
    const auto [it, fresh] = seen.emplace(field.text, field.position);
    if (!fresh && !field.text.empty()) {
      throw InputError({path, header.line, field.position},
                       "column '" + field.text + "' appears twice in the header (fields " +
                           std::to_string(it->second) + " and " + std::to_string(field.position) +
                           ")",
                       "Rename one of them: the mapping names a column by its header");
    }
    table->AddColumn(field.text, header.line, field.position);
  }
}

// One data record as a row; fields beyond the header's are refused, missing ones are empty.
void AddDataRow(const std::string& path, const Record& record, size_t header_fields, char separator,
                DataTable* table) {
  if (record.fields.size() > header_fields) {
    throw InputError({path, record.line, static_cast<int>(header_fields) + 1},
                     "row has " + std::to_string(record.fields.size()) +
                         " fields but the header has " + std::to_string(header_fields) +
                         " (fields separated by " + SeparatorName(separator) + ")",
                     "Remove the extra fields, quote a field that holds the separator, or state "
                     "the separator in the mapping (table: {separator: \";\"})");
  }
  std::vector<std::string> cells;
  std::vector<int> positions;
  for (const auto& field : record.fields) {
    cells.push_back(field.text);
    positions.push_back(field.position);
  }
  for (size_t c = record.fields.size(); c < header_fields; ++c) {
    positions.push_back(static_cast<int>(c) + 1);
  }
  table->AddRow(std::move(cells), record.line, std::move(positions));
}

}  // namespace

DataTable ReadCsvTable(const std::string& path, const CsvDialect& dialect) {
  const std::string text = ReadCsvText(path, dialect.encoding);
  const char separator = SeparatorOf(path, text, dialect);
  const std::vector<Record> records = SplitRecords(path, text, separator);
  if (dialect.encoding == TextEncoding::kUtf8) ExpectUtf8(path, records);
  if (records.empty()) {
    throw InputError({path, 1, 0}, "the table is empty",
                     "The first line must be the header: the name of every column");
  }
  DataTable table(path, "CSV", dialect.decimal);
  AddHeader(path, records.front(), &table);
  for (size_t r = 1; r < records.size(); ++r) {
    AddDataRow(path, records[r], records.front().fields.size(), separator, &table);
  }
  return table;
}

}  // namespace cellmetry
