// Short cells stay on one line.  A table wider than the text column scrolls sideways: say so above it, with how many columns
// are out of sight, and shade its edge (site.css).  Run at load and when the window is resized.
(function () {
  function mark() {
    // a short cell (a number with its unit: "0.1 s", "1,325") is never broken over two lines
    document.querySelectorAll(".md-typeset table:not([class]) td").forEach(function (td) {
      if (td.textContent.trim().length <= 12) td.style.whiteSpace = "nowrap";
    });
    document.querySelectorAll(".md-typeset__scrollwrap").forEach(function (wrap) {
      var table = wrap.querySelector("table");
      var wide = table && wrap.scrollWidth > wrap.clientWidth + 1;
      var hint = wrap.previousElementSibling;
      var has = hint && hint.classList.contains("gc-scroll-hint");
      wrap.classList.toggle("gc-scrolls", !!wide);
      if (!wide) {
        if (has) hint.remove();
        return;
      }
      var right = wrap.getBoundingClientRect().right;
      var hidden = Array.prototype.filter.call(table.rows[0].cells, function (c) {
        return c.getBoundingClientRect().right > right + 1;
      }).length;
      if (!has) {
        hint = document.createElement("div");
        hint.className = "gc-scroll-hint";
        wrap.parentNode.insertBefore(hint, wrap);
      }
      hint.textContent = "\u21c6 wider than the page: scroll the table sideways for " + hidden + " more column" + (hidden === 1 ? "" : "s");
    });
  }
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", mark);
  else mark();
  window.addEventListener("resize", mark);
})();
