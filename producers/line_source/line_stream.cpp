#include "producers/line_source/line_stream.hpp"

#include "producers/csv/fields.hpp"

namespace gyrocal::line_source {

LineStream::LineStream(std::string name, sensor::TempTransfer transfer)
    : name_(std::move(name)), transfer_(transfer) {}

LineOutcome LineStream::Feed(const InputLine& line) {
    using Kind = LineOutcome::Kind;
    ++line_no_;
    LineOutcome out;
    if (fatal_) {
        out.kind = Kind::kFatal;
        out.message = name_ + ": the stream has no valid header; nothing after it is read";
        return out;
    }
    if (line.overlong) {
        out.kind = Kind::kBad;
        out.message = name_ + ":" + std::to_string(line_no_) + ": longer than " +
                      std::to_string(LineInput::kMaxLineBytes) +
                      " bytes; skipped (expected a CSV line)";
        return out;
    }
    if (csv::IsBlankOrComment(line.text)) return out;
    if (!parser_) {
        try {
            csv::Header h = csv::ParseHeader(line.text, name_, line_no_);
            out.unknown_columns = h.unknown;
            parser_.emplace(std::move(h), name_, transfer_);
            header_text_ = line.text;
            out.kind = Kind::kHeader;
        } catch (const csv::CsvError& e) {
            fatal_ = true;
            out.kind = Kind::kFatal;
            out.message =
                std::string(e.what()) + " (the first line of the stream must be the header)";
        }
        return out;
    }
    if (line.text == header_text_) return out;  // a DAQ that restarts may print its header again
    try {
        out.row = parser_->Parse(line.text, line_no_);
        out.kind = Kind::kRow;
    } catch (const csv::CsvError& e) {
        out.kind = Kind::kBad;
        out.message = std::string(e.what()) + "; line skipped";
    }
    return out;
}

}  // namespace gyrocal::line_source
