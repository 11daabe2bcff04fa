// Short cells stay on one line.  A table wider than the text column scrolls sideways: say so above it, with how many columns
// are out of sight, and shade its edge (site.css); a displayed formula wider than the page (a phone) gets the same cue.
// Run at load and when the window is resized.
(function () {
  function tables() {
    // a short cell (a number with its unit: "0.1 s", "1,325") is never broken over two lines
    document.querySelectorAll(".md-typeset table:not([class]) td").forEach(function (td) {
      if (td.textContent.trim().length <= 12) td.style.whiteSpace = "nowrap";
    });
    document.querySelectorAll(".md-typeset__scrollwrap").forEach(function (wrap) {
      var table = wrap.querySelector("table");
      var wide = table && wrap.scrollWidth > wrap.clientWidth + 1;
      var hint = wrap.previousElementSibling;
      var has = hint && hint.classList.contains("gc-scroll-hint");
      var right = wrap.getBoundingClientRect().right;
      var hidden = wide ? Array.prototype.filter.call(table.rows[0].cells, function (c) {
        return c.getBoundingClientRect().right > right + 1;
      }).length : 0;
      wrap.classList.toggle("gc-scrolls", hidden > 0);
      if (!hidden) {  // (a table a few pixels wider than the page hides no column: no cue)
        if (has) hint.remove();
        return;
      }
      if (!has) {
        hint = document.createElement("div");
        hint.className = "gc-scroll-hint";
        wrap.parentNode.insertBefore(hint, wrap);
      }
      hint.textContent = "\u21c6 wider than the page: scroll the table sideways for " + hidden + " more column" + (hidden === 1 ? "" : "s");
    });
  }
  function formulas() {
    // a displayed formula wider than the page (a phone) scrolls sideways: shade its edge and say so
    document.querySelectorAll(".md-typeset .gc-display").forEach(function (box) {
      var wide = box.scrollWidth > box.clientWidth + 1;
      var hint = box.previousElementSibling;
      var has = hint && hint.classList.contains("gc-scroll-hint");
      box.classList.toggle("gc-scrolls", wide);
      if (!wide) {
        if (has) hint.remove();
        return;
      }
      if (!has) {
        hint = document.createElement("div");
        hint.className = "gc-scroll-hint";
        hint.textContent = "\u21c6 wider than the page: scroll the formula sideways";
        box.parentNode.insertBefore(hint, box);
      }
    });
  }
  function mark() {
    tables();
    formulas();
  }
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", mark);
  else mark();
  window.addEventListener("resize", mark);
})();
