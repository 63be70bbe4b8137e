// The site's math: Sphinx writes each formula as \( ... \) or \[ ... \] in an
// element of class "math"; KaTeX (from Debian's libjs-katex, copied into
// _static/katex by docs/conf.py) renders it in place. Nothing is loaded from
// the network. A formula KaTeX cannot read stays as text, marked katex-error.
// Included on every page (and by Sphinx's math extension on pages with
// formulas): it runs once.
if (!window.cubecalMath) {
window.cubecalMath = true;
document.addEventListener("DOMContentLoaded", function () {
  if (typeof renderMathInElement !== "function") return;
  document.querySelectorAll(".math").forEach(function (el) {
    renderMathInElement(el, {
      delimiters: [
        { left: "\\[", right: "\\]", display: true },
        { left: "\\(", right: "\\)", display: false },
      ],
      throwOnError: false,
    });
  });
  document.documentElement.dataset.mathRendered = "yes";
});
}
