"""Type stubs of the native module `flexflight._native` (Rust, PyO3): the binding of the
operations layer. Users call the `flexflight` package, which wraps these."""

from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

__version__: str

def check(files: Sequence[str], sets: Sequence[str]) -> List[Dict[str, Any]]:
    """Every diagnostic of the files, as the dicts of `flexflight check --format json`."""

class NativeProject:
    def __init__(self, files: Sequence[str], sets: Sequence[str], cache_dir: Optional[str] = None) -> None: ...
    def warnings(self) -> List[Dict[str, Any]]: ...
    def names(self) -> Tuple[List[str], List[str], List[str]]: ...
    def compile(self, vehicle: Optional[str] = None) -> Dict[str, Any]: ...
    def run(
        self,
        scenario: str,
        flutter_margin: Optional[bool] = None,
        progress: Optional[Callable[[float, float], Any]] = None,
    ) -> Tuple["NativeRun", List[str]]: ...
    def flutter(
        self,
        scenario: str,
        clamped: bool,
        altitude: Optional[float] = None,
        mach: Optional[float] = None,
        speeds: Optional[Sequence[float]] = None,
        modes: Optional[int] = None,
        aero: str = "doublet-lattice",
    ) -> Tuple[Dict[str, Any], str, List[str]]: ...
    def linear(self, scenario: str, frozen_gravity: bool = False) -> Tuple[Dict[str, Any], List[str]]: ...
    def sweep(
        self,
        name: str,
        out: str,
        jobs: Optional[int] = None,
        shard: Optional[str] = None,
        progress: Optional[Callable[[int, int], Any]] = None,
    ) -> Tuple[Dict[str, Any], List[str]]: ...
    def montecarlo(
        self,
        name: str,
        out: str,
        samples: Optional[int] = None,
        jobs: Optional[int] = None,
        shard: Optional[str] = None,
        flutter_margin: Optional[bool] = None,
        progress: Optional[Callable[[int, int], Any]] = None,
        full_outputs: bool = False,
        exact_boundaries: bool = False,
    ) -> Tuple[Dict[str, Any], List[str]]: ...

class NativeRun:
    def summary(self) -> Dict[str, Any]: ...
    def history(self) -> Tuple[List[str], int, bytes]: ...
    def history_csv(self) -> str: ...
    def flutter_margin_csv(self) -> Optional[str]: ...
    def events(self) -> Dict[str, Any]: ...
    def drag_curve(self) -> Optional[Tuple[float, List[Tuple[float, float]]]]: ...
    def write(self, out: str) -> None: ...
