// CSV tables: the one reader (and writer) for every CSV file welkin reads or writes (measured
// skies, star catalogues, benchmark results). Private to the build tree (engine/private: never
// installed): the astronomy, the welkin command and the tests link welkin_engine_private.
//
//   welkin::CsvTable t = welkin::CsvTable::load("kider2013_scans.csv");
//   const std::size_t alt = t.column("sun_alt_deg");        // throws if the header lacks it
//   for (const welkin::CsvRow& row : t) {
//       double a = row.number(alt);        // "kider2013_scans.csv:7: column 5 'sun_alt_deg': 'x' is not a number"
//       std::string_view file = row.text("csv");
//   }
//   std::vector<double> y = t.numbers("Y");                   // a whole column
//
//   welkin::CsvWriter w("bench.csv", {"preset", "rms_rel"});
//   w.comment("welkin bench sky, 2026-11-23");                // "# ..." line, skipped by the reader
//   w.row(2, 0.0093);
//   w.close();                                                // written atomically (temp + rename)
//
// Format (RFC 4180 plus comments): fields separated by ','; a field may be quoted with '"' (then
// it may hold ',', newlines and '""' for one quote); spaces and tabs around an unquoted field, or
// outside the quotes of a quoted one, are dropped; "\r\n" and "\n" end records; a blank line and a
// line whose first non-blank character is '#' (at the start of a record) are skipped. The first
// record is the header. Every error is one line "source:line: message" (line 1-based, the line
// where the record starts).
#pragma once
#include <charconv>
#include <cstddef>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace welkin {

struct CsvReadOptions {
    /// Match column names ignoring ASCII case (catalogues whose header case varies).
    bool caseInsensitiveColumns = false;
    /// Every data record must have as many fields as the header (else an error naming the line).
    bool sameFieldCount = true;
};

class CsvTable;

/// One data record of a CsvTable (a view: valid while the table lives).
class CsvRow {
public:
    /// 1-based line of the source where the record starts.
    std::size_t line() const;
    /// Number of fields of this record.
    std::size_t size() const;
    /// Field `column` (0-based), unquoted; "" when the record is shorter.
    std::string_view text(std::size_t column) const;
    /// Field of the named column (throws if the header has no such column).
    std::string_view text(std::string_view column) const;
    /// Field `column` as a double (std::from_chars; a leading '+' allowed; "nan"/"inf" accepted).
    /// Throws welkin::Error "source:line: column N 'name': 'text' is not a number" (or ": empty, expected a number").
    double number(std::size_t column) const;
    double number(std::string_view column) const;
    /// As number(), but an empty field gives `fallback`.
    double numberOr(std::size_t column, double fallback) const;
    double numberOr(std::string_view column, double fallback) const;
    /// Throws welkin::Error "source:line: what".
    [[noreturn]] void fail(const std::string& what) const;

private:
    friend class CsvTable;
    CsvRow(const CsvTable* table, std::size_t index) : table_(table), index_(index) {}
    double parseNumber(std::size_t column, const double* fallback) const;
    const CsvTable* table_;
    std::size_t index_;
};

/// A parsed CSV file: header names and data records (strings; numbers parsed on access).
class CsvTable {
public:
    /// Reads and parses `path`. Throws welkin::Error "path: cannot open" or a parse error.
    static CsvTable load(const std::string& path, const CsvReadOptions& options = {});
    /// Parses in-memory text; `sourceName` names it in errors.
    static CsvTable parse(std::string_view text, const std::string& sourceName, const CsvReadOptions& options = {});

    const std::string& source() const { return source_; }
    /// Column names (trimmed); empty for a text with no record.
    const std::vector<std::string>& header() const { return header_; }
    /// 1-based line of the header (0 if none).
    std::size_t headerLine() const { return headerLine_; }
    /// Index of the named column, or nothing.
    std::optional<std::size_t> findColumn(std::string_view name) const;
    /// Index of the named column; throws welkin::Error "source:line: no column 'name' (columns: a, b)".
    std::size_t column(std::string_view name) const;
    /// Every value of the named column as numbers (errors as CsvRow::number()).
    std::vector<double> numbers(std::string_view column) const;

    std::size_t rowCount() const { return records_.size(); }
    CsvRow row(std::size_t index) const { return CsvRow(this, index); }

    class Iterator {
    public:
        CsvRow operator*() const { return table_->row(index_); }
        Iterator& operator++() { return ++index_, *this; }
        bool operator!=(const Iterator& o) const { return index_ != o.index_; }

    private:
        friend class CsvTable;
        Iterator(const CsvTable* t, std::size_t i) : table_(t), index_(i) {}
        const CsvTable* table_;
        std::size_t index_;
    };
    Iterator begin() const { return Iterator(this, 0); }
    Iterator end() const { return Iterator(this, records_.size()); }

private:
    friend class CsvRow;
    struct Record {
        std::size_t line;
        std::vector<std::string> fields;
    };
    std::string source_;
    CsvReadOptions options_;
    std::vector<std::string> header_;
    std::size_t headerLine_ = 0;
    std::vector<Record> records_;
};

/// Writes a CSV file: a header, then rows of strings and numbers. Fields holding ',', '"', '#'
/// (first character), spaces at either end or newlines are quoted; doubles are written in the
/// shortest form that reads back exactly (std::to_chars), NaN as "nan". The file is written to a
/// temporary name and renamed by close() (or the destructor): a failure never leaves a partial file.
class CsvWriter {
public:
    /// Throws welkin::Error "CsvWriter: cannot write 'path'" if the file cannot be created.
    CsvWriter(std::string path, const std::vector<std::string>& header);
    CsvWriter(const CsvWriter&) = delete;
    CsvWriter& operator=(const CsvWriter&) = delete;
    /// Closes if not yet closed (errors are then swallowed: call close() to see them).
    ~CsvWriter();

    /// A "# text" line (one per line of `text`); comments made before the first row precede the header.
    void comment(std::string_view text);
    /// One row of exactly header().size() values (strings, integers or floating point).
    template <class... T>
    void row(const T&... values) {
        std::vector<std::string> fields;
        fields.reserve(sizeof...(T));
        (fields.push_back(format(values)), ...);
        writeFields(fields);
    }
    /// One row of already formatted fields (quoted as needed).
    void writeFields(const std::vector<std::string>& fields);
    /// Flushes and renames the temporary file onto the path. Throws welkin::Error naming the path.
    void close();

    static std::string format(double v);
    static std::string format(std::string_view s) { return std::string(s); }
    static std::string format(const std::string& s) { return s; }
    static std::string format(const char* s) { return s; }
    template <class I, std::enable_if_t<std::is_integral_v<I>, int> = 0>
    static std::string format(I v) {
        return std::to_string(v);
    }
    template <class F, std::enable_if_t<std::is_floating_point_v<F> && !std::is_same_v<F, double>, int> = 0>
    static std::string format(F v) {
        return format(double(v));
    }

private:
    void writeRecord(const std::vector<std::string>& fields);
    std::string path_, tmp_;
    std::vector<std::string> header_;
    std::ofstream out_;
    bool headerWritten_ = false;  // written before the first row: comment()s before it go above it
    bool closed_ = false;
};

}  // namespace welkin
