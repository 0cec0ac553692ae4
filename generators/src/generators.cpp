// The generators library; LUT generators are added beside this file (one .cpp each).
namespace welkin::generators {
/// Library version marker (keeps the archive non-empty until generators land).
int libraryRevision() { return 1; }
}  // namespace welkin::generators
