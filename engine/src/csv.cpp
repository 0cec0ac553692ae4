// CSV reader and writer (csv.hpp).
#include <welkin/csv.hpp>
#include <welkin/error.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace welkin {

namespace {

bool isBlank(char c) { return c == ' ' || c == '\t'; }

std::string_view trim(std::string_view s) {
    while (!s.empty() && isBlank(s.front())) s.remove_prefix(1);
    while (!s.empty() && isBlank(s.back())) s.remove_suffix(1);
    return s;
}

bool equalNames(std::string_view a, std::string_view b, bool ignoreCase) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        char x = a[i], y = b[i];
        if (ignoreCase) {
            if (x >= 'A' && x <= 'Z') x = char(x - 'A' + 'a');
            if (y >= 'A' && y <= 'Z') y = char(y - 'A' + 'a');
        }
        if (x != y) return false;
    }
    return true;
}

[[noreturn]] void failAt(const std::string& source, std::size_t line, const std::string& what) {
    throw Error(source + ":" + std::to_string(line) + ": " + what);
}

}  // namespace

// ---- CsvTable

CsvTable CsvTable::load(const std::string& path, const CsvReadOptions& options) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open");
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw Error(path + ": read error");
    return parse(ss.str(), path, options);
}

CsvTable CsvTable::parse(std::string_view text, const std::string& sourceName, const CsvReadOptions& options) {
    CsvTable t;
    t.source_ = sourceName;
    t.options_ = options;
    std::size_t line = 1;  // current physical line
    std::size_t i = 0;
    const std::size_t n = text.size();
    while (i < n) {
        // Start of a record: skip a comment line.
        std::size_t j = i;
        while (j < n && isBlank(text[j])) ++j;
        if (j < n && text[j] == '#') {
            while (i < n && text[i] != '\n') ++i;
            if (i < n) ++i, ++line;
            continue;
        }
        const std::size_t recordLine = line;
        std::vector<std::string> fields;
        std::string cur;
        bool quoted = false;    // this field had quotes
        bool inQuotes = false;  // inside them now
        bool endOfRecord = false;
        auto endField = [&] {
            fields.push_back(quoted ? cur : std::string(trim(cur)));
            cur.clear();
            quoted = false;
        };
        while (i < n && !endOfRecord) {
            const char c = text[i++];
            if (inQuotes) {
                if (c == '"') {
                    if (i < n && text[i] == '"') cur += '"', ++i;
                    else inQuotes = false;
                } else {
                    if (c == '\n') ++line;
                    cur += c;
                }
            } else if (c == ',') {
                endField();
            } else if (c == '\n' || c == '\r') {
                if (c == '\r' && i < n && text[i] == '\n') ++i;
                ++line;
                endOfRecord = true;
            } else if (c == '"') {
                if (quoted || !trim(cur).empty())
                    failAt(sourceName, recordLine, "field " + std::to_string(fields.size() + 1) + ": '\"' inside an unquoted field");
                quoted = inQuotes = true;
                cur.clear();
            } else if (quoted) {
                if (!isBlank(c))
                    failAt(sourceName, recordLine, "field " + std::to_string(fields.size() + 1) + ": text after the closing '\"'");
            } else {
                cur += c;
            }
        }
        if (inQuotes) failAt(sourceName, recordLine, "unterminated quote");
        const bool blank = fields.empty() && !quoted && trim(cur).empty();
        endField();
        if (blank) continue;
        if (t.headerLine_ == 0) {
            t.header_ = std::move(fields);
            t.headerLine_ = recordLine;
            continue;
        }
        if (options.sameFieldCount && fields.size() != t.header_.size())
            failAt(sourceName, recordLine,
                   "expected " + std::to_string(t.header_.size()) + " fields, found " + std::to_string(fields.size()));
        t.records_.push_back({recordLine, std::move(fields)});
    }
    return t;
}

std::optional<std::size_t> CsvTable::findColumn(std::string_view name) const {
    for (std::size_t k = 0; k < header_.size(); ++k)
        if (equalNames(header_[k], name, options_.caseInsensitiveColumns)) return k;
    return std::nullopt;
}

std::size_t CsvTable::column(std::string_view name) const {
    if (auto k = findColumn(name)) return *k;
    std::string list;
    for (const auto& h : header_) list += (list.empty() ? "" : ", ") + h;
    failAt(source_, std::max<std::size_t>(headerLine_, 1),
           "no column '" + std::string(name) + "' (columns: " + (list.empty() ? "none" : list) + ")");
}

std::vector<double> CsvTable::numbers(std::string_view name) const {
    const std::size_t k = column(name);
    std::vector<double> v;
    v.reserve(records_.size());
    for (const CsvRow& r : *this) v.push_back(r.number(k));
    return v;
}

// ---- CsvRow

std::size_t CsvRow::line() const { return table_->records_[index_].line; }
std::size_t CsvRow::size() const { return table_->records_[index_].fields.size(); }

std::string_view CsvRow::text(std::size_t column) const {
    const auto& f = table_->records_[index_].fields;
    return column < f.size() ? std::string_view(f[column]) : std::string_view();
}

std::string_view CsvRow::text(std::string_view column) const { return text(table_->column(column)); }

double CsvRow::parseNumber(std::size_t column, const double* fallback) const {
    const std::string_view s = trim(text(column));
    auto name = [&] {
        const auto& h = table_->header_;
        return "column " + std::to_string(column + 1) + (column < h.size() ? " '" + h[column] + "'" : std::string());
    };
    if (s.empty()) {
        if (fallback) return *fallback;
        fail(name() + ": empty, expected a number");
    }
    std::string_view digits = s;
    if (digits.front() == '+') digits.remove_prefix(1);
    double v = 0;
    auto [p, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    if (digits.empty() || ec != std::errc() || p != digits.data() + digits.size())
        fail(name() + ": '" + std::string(s) + "' is not a number");
    return v;
}

double CsvRow::number(std::size_t column) const { return parseNumber(column, nullptr); }
double CsvRow::numberOr(std::size_t column, double fallback) const { return parseNumber(column, &fallback); }
double CsvRow::number(std::string_view column) const { return number(table_->column(column)); }
double CsvRow::numberOr(std::string_view column, double fallback) const { return numberOr(table_->column(column), fallback); }

void CsvRow::fail(const std::string& what) const { failAt(table_->source_, line(), what); }

// ---- CsvWriter

namespace {

bool needsQuotes(std::string_view s) {
    if (s.empty()) return false;
    if (s.front() == '#' || isBlank(s.front()) || isBlank(s.back())) return true;
    return s.find_first_of(",\"\r\n") != std::string_view::npos;
}

std::string quoteField(std::string_view s) {
    if (!needsQuotes(s)) return std::string(s);
    std::string out = "\"";
    for (char c : s) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + '"';
}

}  // namespace

CsvWriter::CsvWriter(std::string path, const std::vector<std::string>& header)
    : path_(std::move(path)), tmp_(path_ + ".tmp"), header_(header) {
    if (header.empty()) throw Error("CsvWriter: '" + path_ + "': empty header");
    out_.open(tmp_, std::ios::binary | std::ios::trunc);
    if (!out_) throw Error("CsvWriter: cannot write '" + path_ + "'");
}

CsvWriter::~CsvWriter() {
    if (closed_) return;
    try {
        close();
    } catch (...) {
        std::error_code ec;
        std::filesystem::remove(tmp_, ec);
    }
}

void CsvWriter::comment(std::string_view text) {
    if (closed_) throw Error("CsvWriter: '" + path_ + "' already closed");
    std::size_t start = 0;
    while (true) {
        const std::size_t end = text.find('\n', start);
        out_ << "# " << text.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start) << '\n';
        if (end == std::string_view::npos) break;
        start = end + 1;
    }
}

void CsvWriter::writeRecord(const std::vector<std::string>& fields) {
    for (std::size_t k = 0; k < fields.size(); ++k) out_ << (k ? "," : "") << quoteField(fields[k]);
    out_ << '\n';
}

void CsvWriter::writeFields(const std::vector<std::string>& fields) {
    if (closed_) throw Error("CsvWriter: '" + path_ + "' already closed");
    if (fields.size() != header_.size())
        throw Error("CsvWriter: '" + path_ + "': row of " + std::to_string(fields.size()) + " fields, header has " +
                    std::to_string(header_.size()));
    if (!headerWritten_) writeRecord(header_), headerWritten_ = true;
    writeRecord(fields);
}

void CsvWriter::close() {
    if (closed_) return;
    if (!headerWritten_) writeRecord(header_), headerWritten_ = true;
    closed_ = true;
    out_.close();
    if (!out_) {
        std::error_code ec;
        std::filesystem::remove(tmp_, ec);
        throw Error("CsvWriter: cannot write '" + path_ + "'");
    }
    std::error_code ec;
    std::filesystem::rename(tmp_, path_, ec);
    if (ec) {
        std::filesystem::remove(tmp_, ec);
        throw Error("CsvWriter: cannot rename onto '" + path_ + "'");
    }
}

std::string CsvWriter::format(double v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[32];
    auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, p);
}

}  // namespace welkin
