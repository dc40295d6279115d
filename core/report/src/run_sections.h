// The run report's sections (internal): each appends to a page from a WorkcellResult.
#pragma once

#include "cellmetry/cell/workcell_result.h"
#include "cellmetry/formats/recording.h"
#include "cellmetry/report/html_page.h"

namespace cellmetry::report {

void ResidualOrderSection(const WorkcellResult& r, const Recording& recording, HtmlPage* page);
void WhitenedSection(const WorkcellResult& r, HtmlPage* page);
void ResidualImageSection(const WorkcellResult& r, const Recording& recording, HtmlPage* page);
void SigmaSection(const WorkcellResult& r, HtmlPage* page);
void CorrelationSection(const WorkcellResult& r, HtmlPage* page);
void OutlierSection(const WorkcellResult& r, const Recording& recording, HtmlPage* page);
void HeldOutSection(const WorkcellResult& r, const Recording& recording, HtmlPage* page);
void FramesSection(const WorkcellResult& r, HtmlPage* page);
void CamerasLeftOutSection(const WorkcellResult& r, HtmlPage* page);
void HeldOutSetupSection(const WorkcellResult& r, HtmlPage* page);

}  // namespace cellmetry::report
